// What the mesh programs write (glsl/mesh/phong.frag, pbr.frag): colour, or with OIT the
// weighted blended sums (McGuire and Bavoil 2013: location 0 sums w a C and w a, location 1
// sums -log(1 - a), so that exp(-sum) is the product of the (1 - a) behind which the opaque
// scene shows; w = max(0.01, 3000 (1 - z)^3) favours what is nearer); and the exact
// channels, which exist only when asked for (OUT_<NAME> = its location, see
// facet.gl.targets: outputs nobody reads still cost a software rasteriser time).
// The including stage declares v_pos_world, v_depth_view, v_uv and OBJECT_ID.
layout(location = 0) out vec4 f_color;
#ifdef OIT
layout(location = 1) out float f_reveal;
const float OIT_MAX_OPACITY = 0.999;  // log(1 - a) stays finite
#endif
#ifdef OUT_DEPTH_IDS
// (the bits of the linear depth along the camera axis, object id + 1): one attachment
layout(location = OUT_DEPTH_IDS) out uvec2 f_depth_ids;
#endif
#ifdef OUT_NORMALS
layout(location = OUT_NORMALS) out vec4 f_normal;  // world space, facing the viewer
#endif
#ifdef OUT_POSITION
layout(location = OUT_POSITION) out vec4 f_position;  // world space
#endif
#ifdef OUT_UV
layout(location = OUT_UV) out vec2 f_uv;
#endif

// The exact channels but the normal (written once the shading normal is known).
void write_exact() {
#ifdef OUT_DEPTH_IDS
    f_depth_ids = uvec2(floatBitsToUint(v_depth_view), uint(OBJECT_ID));
#endif
#ifdef OUT_POSITION
    f_position = vec4(v_pos_world, 1.0);
#endif
#ifdef OUT_UV
    f_uv = v_uv;
#endif
}

void write_normal(vec3 N) {
#ifdef OUT_NORMALS
    f_normal = vec4(N, 0.0);
#endif
}

// The colour of this fragment, of opacity a (OIT: into the sums; else opaque).
void write_color(vec3 rgb, float a) {
#ifdef OIT
    a = clamp(a, 0.0, OIT_MAX_OPACITY);
    float w = max(0.01, 3000.0 * pow(1.0 - gl_FragCoord.z, 3.0));
    f_color = vec4(rgb * a, a) * w;
    f_reveal = -log(1.0 - a);
#else
    f_color = vec4(rgb, 1.0);
#endif
}
