#version 330 core
#ifdef SCENE_IMAGES  // (glsl/trace/data.glsl)
#extension GL_ARB_shader_image_load_store : require
#extension GL_ARB_shading_language_420pack : require
#endif
// The exact channels of the ray tracer: the nearest opaque surface on the ray through each
// pixel's centre (the pinhole camera, no shift), written like the rasterizer's
// (facet.gl.targets): linear depth along the camera axis, object id + 1, the normal facing
// the viewer, the world position and the texture coordinates; 0 where nothing is hit.
// ALBEDO (the path tracer's materials): the first hit's albedo into the colour, the
// denoiser's guide (facet.render.denoise): the base colour, white where a smooth
// dielectric lets light through.
#include "trace/shade.glsl"
#ifdef PBR_SLOTS
#include "trace/material.glsl"
#endif

uniform mat4 u_inv_view_projection;
uniform vec2 u_viewport;
uniform vec3 u_eye_world;
uniform vec3 u_forward;  // the camera's viewing direction (unit)

layout(location = 0) out vec4 f_color;
#ifdef OUT_DEPTH_IDS
// (the bits of the linear depth along the camera axis, object id + 1): one attachment
layout(location = OUT_DEPTH_IDS) out uvec2 f_depth_ids;
#endif
#ifdef OUT_NORMALS
layout(location = OUT_NORMALS) out vec4 f_normal;
#endif
#ifdef OUT_POSITION
layout(location = OUT_POSITION) out vec4 f_position;
#endif
#ifdef OUT_UV
layout(location = OUT_UV) out vec2 f_uv;
#endif

void main() {
    vec2 ndc = gl_FragCoord.xy / u_viewport * 2.0 - 1.0;
    vec4 near = u_inv_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far = u_inv_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 o = near.xyz / near.w;
    vec3 span = far.xyz / far.w - o;
    vec3 d = normalize(span);
    float t_max = length(span);
    Hit h;
    for (int k = 0; k < 64; ++k) {  // one call site: each inlines a whole traversal
        g_camera_ray = true;  // (nothing else is traced here)
        h = trace_scene(o, d, t_max, true);
#ifdef PBR_SLOTS
        // The path tracer's materials: cut-outs (alpha MASK) are not there, as rasterized.
        if (h.inst < 0) break;
        Surface c = surface_at(h, o, d);
        if (!cut_out(c)) break;
        o = offset_ray(c.p, -c.ng);
        t_max -= h.t;
#else
        break;
#endif
    }
    if (h.inst < 0) discard;  // the targets were cleared to 0
    f_color = vec4(0.0);
// (depth and ids need no surface: llvmpipe would run all of surface_at's fetches for
// every pixel, hit or not; 10-15% of an ids pass)
#if defined(OUT_NORMALS) || defined(OUT_POSITION) || defined(OUT_UV) || defined(ALBEDO)
    Surface s = surface_at(h, o, d);
#endif
#if defined(ALBEDO) && defined(PBR_SLOTS)
    Material m = material_of(s);
    f_color = vec4(m.unlit ? m.base : mix(m.base, vec3(1.0),
                                          m.transmission * (1.0 - m.metallic)), 1.0);
#endif
#ifdef OUT_DEPTH_IDS
    // Linear depth along the camera axis: (p - eye) . forward, p = o + t d the hit (t is
    // the world ray's); a parallel projection's "eye" is any point on its axis plane, the
    // same formula holds.
    f_depth_ids = uvec2(floatBitsToUint(dot(o + h.t * d - u_eye_world, u_forward)),
                        uint(int(instance_texel(h.inst * INSTANCE_TEXELS + 6).z) + 1));
#endif
#ifdef OUT_NORMALS
    f_normal = vec4(s.n, 0.0);
#endif
#ifdef OUT_POSITION
    f_position = vec4(s.p, 1.0);
#endif
#ifdef OUT_UV
    f_uv = s.uv;
#endif
}
