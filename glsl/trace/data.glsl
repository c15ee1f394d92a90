// The ray tracer's scene in textures (packed by facet.render.rays.pack): rows of TEX_WIDTH
// texels, element i at (i mod TEX_WIDTH, i / TEX_WIDTH). Object space for meshes and shapes,
// world space for instances and the top level; read by texelFetch or imageLoad (below).
// The layout's constants (TEX_SHIFT, NODE_TEXELS, VERTEX_TEXELS, INSTANCE_TEXELS,
// MATERIAL_ROW, SLOT_ROW, SLOT_TEXELS, the KIND_* and FLAG_* values) are
// facet.render.rays.pack's, defined by facet when it compiles these files
// (pack.layout_defines).
#ifndef NODE_TEXELS
#error the tracer's layout is defined by facet.render.rays.pack (layout_defines)
#endif
const int TEX_MASK = (1 << TEX_SHIFT) - 1;

// The scene's arrays: where the context lists image load and store and layout bindings
// (two extensions, core in GL 4.2: SCENE_IMAGES, facet.render.rays.scene reads_images)
// they are read through image units (facet.gl.bindings.IMAGES, their IMAGE_* defines);
// otherwise by texelFetch. On llvmpipe an imageLoad costs about two thirds of a
// texelFetch, which works out a mip level, its size and its offset for every lane (a chain
// of dependent reads of a 1 MB texture: 840M against 570M a second; the path tracer on
// mesh scenes 13-27% faster, and faster than uniform blocks for small scenes' rows).
#ifdef SCENE_IMAGES
layout(binding = IMAGE_TRIS, rgba32f) readonly uniform image2D u_tris;
layout(binding = IMAGE_TRI_INDEX, rgba32i) readonly uniform iimage2D u_tri_index;
layout(binding = IMAGE_VERTICES, rgba32f) readonly uniform image2D u_vertices;
layout(binding = IMAGE_NODES, rgba32ui) readonly uniform uimage2D u_nodes;
layout(binding = IMAGE_INSTANCES, rgba32f) readonly uniform image2D u_instances;
layout(binding = IMAGE_TLAS, rgba32f) readonly uniform image2D u_tlas;
#define TEXEL(array, i) imageLoad(array, ivec2((i) & TEX_MASK, (i) >> TEX_SHIFT))
#else
uniform sampler2D u_tris;
uniform isampler2D u_tri_index;
uniform sampler2D u_vertices;
uniform usampler2D u_nodes;
uniform sampler2D u_instances;
uniform sampler2D u_tlas;
#define TEXEL(array, i) texelFetch(array, ivec2((i) & TEX_MASK, (i) >> TEX_SHIFT), 0)
#endif
// u_tris: 3 texels per triangle: v0, e1 = v1 - v0, e2 = v2 - v0
// u_tri_index: 1 texel per triangle: its vertices' indices
// u_vertices: VERTEX_TEXELS per vertex: (normal, u), (v, colour rgb), (tangent xyz,
//     handedness), (uv1, colour alpha, 0)
// u_nodes: meshes' hierarchies: per mesh a header, then MESH_NODE_TEXELS per inner node
//     (quantised boxes: facet.render.rays.pack pack_mesh_nodes)
// u_instances: INSTANCE_TEXELS per placed object (see scene.glsl)
// u_tlas: the top level over instances, float nodes (below)
uniform int u_unbounded;         // instances [0, u_unbounded) are infinite: not in u_tlas
uniform bool u_has_tlas;         // false: at most one bounded instance, u_single
uniform int u_single;            // that instance, or -1

const float INF = 1e30;
// A top-level node holds both children's boxes: texels (left lo, ref), (left hi, count),
// (right lo, ref), (right hi, count). ref >= 0: an inner child's node index; ref < 0: a leaf
// of count elements starting at -ref - 1 (an empty child: a leaf of 0; NODE_TEXELS = 4). A
// mesh's nodes are quantised, a texel a child (trace/bvh.glsl trace_mesh).

vec4 fetch(sampler2D s, int i) {  // (a texture of the same layout: the emitters')
    return texelFetch(s, ivec2(i & TEX_MASK, i >> TEX_SHIFT), 0);
}

// A small scene's instance rows and top level in uniform blocks of SCENE_BLOCKS texels
// (facet.render.rays.scene: on llvmpipe far cheaper than texel fetches), else in their
// textures.
#ifdef SCENE_BLOCKS
layout(std140) uniform Instances { vec4 u_instance_rows[SCENE_BLOCKS]; };
layout(std140) uniform Tlas { vec4 u_tlas_rows[SCENE_BLOCKS]; };
vec4 instance_texel(int i) { return u_instance_rows[i]; }
vec4 tlas_texel(int i) { return u_tlas_rows[i]; }
#else
vec4 instance_texel(int i) { return TEXEL(u_instances, i); }
vec4 tlas_texel(int i) { return TEXEL(u_tlas, i); }
#endif

// 1 / d with zero components replaced by a tiny number of the same sign: the slab test
// then sees huge finite distances instead of 0 * inf (node boxes are padded for grazing
// rays; facet.geometry.bvh).
vec3 safe_inverse(vec3 d) {
    vec3 tiny = vec3(1e-30);
    return 1.0 / mix(d, mix(-tiny, tiny, step(0.0, d)), lessThan(abs(d), tiny));
}

// Entry distance of the ray into box [lo, hi] within [0, t_max], or INF when it misses.
float box_entry(vec3 lo, vec3 hi, vec3 o, vec3 inv_d, float t_max) {
    vec3 t0 = (lo - o) * inv_d;
    vec3 t1 = (hi - o) * inv_d;
    vec3 near3 = min(t0, t1);
    vec3 far3 = max(t0, t1);
    float near = max(max(near3.x, near3.y), max(near3.z, 0.0));
    float far = min(min(far3.x, far3.y), min(far3.z, t_max));
    return near <= far ? near : INF;
}
