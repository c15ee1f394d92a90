// The Book of Shaders / glslViewer style: its own main(), gl_FragColor, u_time,
// u_resolution and u_mouse. facet runs it as it is: facet shader glsl/examples/book.frag
#ifdef GL_ES
precision mediump float;
#endif

uniform vec2 u_resolution;
uniform vec2 u_mouse;
uniform float u_time;

float circle(vec2 st, vec2 centre, float radius) {
    return 1.0 - smoothstep(radius - 0.01, radius + 0.01, distance(st, centre));
}

void main() {
    vec2 st = gl_FragCoord.xy / u_resolution.xy;
    st.x *= u_resolution.x / u_resolution.y;
    vec3 color = vec3(st.x / 2.0, st.y, abs(sin(u_time)));
    vec2 mouse = u_mouse / u_resolution.y;
    color = mix(color, vec3(1.0), circle(st, mouse, 0.1));
    gl_FragColor = vec4(color, 1.0);
}
