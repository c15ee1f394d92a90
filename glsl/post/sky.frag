#version 330 core
// The environment as background: the world direction through each pixel, looked up in the
// cube map. u_inv_view_projection takes window NDC back to world space.
uniform samplerCube u_environment;
uniform mat4 u_inv_view_projection;
uniform vec2 u_viewport;  // pixels
out vec4 f_color;

void main() {
    vec2 ndc = gl_FragCoord.xy / u_viewport * 2.0 - 1.0;
    vec4 near = u_inv_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far = u_inv_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - near.xyz / near.w);
    f_color = vec4(texture(u_environment, dir).rgb, 1.0);
}
