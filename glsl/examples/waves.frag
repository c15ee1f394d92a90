// Shadertoy-style: colour waves that follow the mouse (drag in the window).
// Try: facet shader glsl/examples/waves.frag
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 uv = fragCoord / iResolution.xy;
    vec2 centre = iMouse.z > 0.0 ? iMouse.xy / iResolution.xy : vec2(0.5);
    float d = length((uv - centre) * vec2(iResolution.x / iResolution.y, 1.0));
    float wave = 0.5 + 0.5 * sin(30.0 * d - 4.0 * iTime);
    vec3 color = 0.5 + 0.5 * cos(iTime + uv.xyx * 3.0 + vec3(0.0, 2.0, 4.0));
    fragColor = vec4(color * (0.6 + 0.4 * wave), 1.0);
}
