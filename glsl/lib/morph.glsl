// Morph targets in the vertex shader (facet.scene.skinned): position, normal and tangent
// displacements, weighted, added to the rest vertex before skinning. The displacements
// come as texels, MORPH_WIDTH a row: texel 3 (t N + v) holds target t's displacement of
// vertex v's position, the next ones its normal's and its tangent's (zero where the file
// gives none).
uniform sampler2D u_targets;
uniform float u_morph_weights[MAX_MORPH];
uniform int u_morph_count;     // targets
uniform int u_morph_vertices;  // N

vec4 morph_texel(int i) {
    return texelFetch(u_targets, ivec2(i % MORPH_WIDTH, i / MORPH_WIDTH), 0);
}

// Texel k of each target (0: position, 1: normal, 2: tangent), weighted and summed.
vec3 morphed(int k) {
    vec3 sum = vec3(0.0);
    for (int t = 0; t < u_morph_count; ++t) {
        float w = u_morph_weights[t];
        if (w != 0.0) sum += w * morph_texel(3 * (t * u_morph_vertices + gl_VertexID) + k).xyz;
    }
    return sum;
}
