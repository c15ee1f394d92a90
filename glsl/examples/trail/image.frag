// Image of the "trail" example: Buffer A's trail (iChannel1 = buffer-a) through a colour
// ramp, over a dark grid drawn here.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 uv = fragCoord / iResolution.xy;
    float t = texture(iChannel1, uv).r;
    vec3 ramp = mix(vec3(0.05, 0.02, 0.2), vec3(1.0, 0.6, 0.1), t) + vec3(t * t);
    vec2 grid = abs(fract(fragCoord / 32.0) - 0.5);
    float line = step(0.47, max(grid.x, grid.y));
    fragColor = vec4(ramp + 0.08 * line * (1.0 - t), 1.0);
}
