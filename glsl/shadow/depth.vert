#version 330 core
// Shadow maps: object space -> the light's clip space; only depth is written.
in vec3 in_position;
#ifdef INSTANCED
in mat4 in_light_mvp;  // per instance (facet.render.raster.instancing), composed in float64
#define LIGHT_MVP in_light_mvp
#else
uniform mat4 u_light_mvp;
#define LIGHT_MVP u_light_mvp
#endif
#ifdef ALPHA_MASK
in vec2 in_uv;
out vec2 v_uv;
#endif
#ifdef SKINNED
#include "lib/skin.glsl"
#endif
#ifdef MORPHED
#include "lib/morph.glsl"
#endif

void main() {
    vec4 position = vec4(in_position, 1.0);
#ifdef MORPHED
    position.xyz += morphed(0);
#endif
#ifdef SKINNED
    position = skin_matrix() * position;
#endif
    gl_Position = LIGHT_MVP * position;
#ifdef ALPHA_MASK
    v_uv = in_uv;
#endif
}
