// Buffer A of the "trail" example: a dot circling the centre leaves a fading trail. It
// reads its own previous frame (iChannel0 = buffer-a) and keeps 96% of it.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 uv = fragCoord / iResolution.xy;
    vec2 centre = 0.5 + 0.3 * vec2(cos(iTime * 2.0), sin(iTime * 3.0));
    float dot_ = smoothstep(0.04, 0.0, distance(uv * vec2(iResolution.x / iResolution.y, 1.0),
                                                centre * vec2(iResolution.x / iResolution.y, 1.0)));
    float previous = texture(iChannel0, uv).r;
    fragColor = vec4(max(previous * 0.96, dot_), 0.0, 0.0, 1.0);
}
