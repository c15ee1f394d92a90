#version 330 core
// Shadow maps: object space -> the light's clip space; only depth is written.
in vec3 in_position;
uniform mat4 u_light_mvp;
#ifdef ALPHA_MASK
in vec2 in_uv;
out vec2 v_uv;
#endif

void main() {
    gl_Position = u_light_mvp * vec4(in_position, 1.0);
#ifdef ALPHA_MASK
    v_uv = in_uv;
#endif
}
