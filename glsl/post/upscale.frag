#version 330 core
// The shader lab's picture, drawn smaller than its window (facet.window.preview), stretched
// over the window's viewport (u_size pixels) with bilinear filtering.
uniform sampler2D u_source;
uniform vec2 u_size;
out vec4 f_color;

void main() {
    f_color = texture(u_source, gl_FragCoord.xy / u_size);
}
