#version 330 core
// World-space normals as colours (n * 0.5 + 0.5): the same picture as --shading normals.
in vec3 v_normal_world;  // the normal matrix (M^-1)^T times the object-space normal

layout(location = 0) out vec4 f_color;

void main() {
    f_color = vec4(normalize(v_normal_world) * 0.5 + 0.5, 1.0);
}
