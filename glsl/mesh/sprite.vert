#version 330 core
// Points and lines (facet.scene.points). A point is a GL point gl_PointSize pixels across
// (its size, or its world radius through the projection at its depth), at its centre's
// depth (the depth and ids channels are exact at the centre); phong.frag rounds it into a
// disc by gl_PointCoord. A line is a quad, one instance per segment, four vertices (a
// triangle strip; the corner from gl_VertexID), its depth interpolated along it. Outputs
// as phong.vert's, so glsl/mesh/phong.frag shades them.

uniform mat4 u_model;         // object -> world
uniform mat4 u_view;          // world -> view
uniform mat4 u_mvp;           // object -> clip, composed in float64
uniform mat3 u_normal_matrix;
uniform vec2 u_viewport;      // pixels
uniform float u_sprite_pixels;  // screen-size: a point's diameter or a line's width (px)
uniform vec2 u_sprite_clip;   // world-size points: radius x (P[0][0], P[1][1]); else 0

#ifdef SPRITE_POINTS
in vec3 in_position;  // per instance, object space
in vec3 in_normal;
#ifdef HAS_VERTEX_COLORS
in vec4 in_color;
#endif
#else  // SPRITE_LINES
in vec3 in_p0;        // per instance: the segment's ends, object space
in vec3 in_p1;
#ifdef HAS_VERTEX_COLORS
in vec4 in_c0;
in vec4 in_c1;
#endif
#endif
#ifdef HAS_VERTEX_COLORS
out vec4 v_color;
#include "lib/color.glsl"
#endif
out vec3 v_pos_world;
out vec3 v_normal_world;
out float v_depth_view;
out vec2 v_uv;
#ifdef SPRITE_LINES
out vec2 v_corner;  // (-1..1, -1..1) across the quad
#endif

const float NEAR_W = 1e-5;  // clip w a line's end is pulled to when behind the eye

void main() {
    v_uv = vec2(0.0);
#ifdef SPRITE_POINTS
    vec3 p = in_position;
    vec4 clip = u_mvp * vec4(p, 1.0);
    gl_Position = clip;
    // World-size: the radius through the projection's y scale at this depth, in pixels.
    gl_PointSize = u_sprite_pixels > 0.0 ? u_sprite_pixels
                                         : u_sprite_clip.y / abs(clip.w) * u_viewport.y;
    v_normal_world = u_normal_matrix * in_normal;
#ifdef HAS_VERTEX_COLORS
    vec4 c = in_color;
#endif
#else
    int k = gl_VertexID;
    vec2 corner = vec2((k & 1) == 0 ? -1.0 : 1.0, (k & 2) == 0 ? -1.0 : 1.0);
    v_corner = corner;
    // Pull an end behind the eye to just in front of it, along the segment.
    vec4 c0 = u_mvp * vec4(in_p0, 1.0), c1 = u_mvp * vec4(in_p1, 1.0);
    vec3 a = in_p0, b = in_p1;
    if (c0.w < NEAR_W && c1.w >= NEAR_W) a = mix(a, b, (NEAR_W - c0.w) / (c1.w - c0.w));
    if (c1.w < NEAR_W && c0.w >= NEAR_W) b = mix(b, a, (NEAR_W - c1.w) / (c0.w - c1.w));
    c0 = u_mvp * vec4(a, 1.0);
    c1 = u_mvp * vec4(b, 1.0);
    bool far_end = corner.y > 0.0;
    vec3 p = far_end ? b : a;
    vec4 clip = far_end ? c1 : c0;
    // Across the segment as the screen shows it, half the width each side (pixels).
    vec2 s0 = c0.xy / c0.w * u_viewport, s1 = c1.xy / c1.w * u_viewport;
    vec2 along = s1 - s0;
    along = dot(along, along) > 0.0 ? normalize(along) : vec2(1.0, 0.0);
    vec2 across = vec2(-along.y, along.x);
    gl_Position = vec4(clip.xy + corner.x * across * u_sprite_pixels / u_viewport * clip.w,
                       clip.zw);
    v_normal_world = vec3(0.0);  // lines are unlit; phong.frag faces them to the viewer
#ifdef HAS_VERTEX_COLORS
    vec4 c = far_end ? in_c1 : in_c0;
#endif
#endif
    vec4 pos_world = u_model * vec4(p, 1.0);
    v_pos_world = pos_world.xyz;
    v_depth_view = -dot(vec4(u_view[0][2], u_view[1][2], u_view[2][2], u_view[3][2]), pos_world);
#ifdef HAS_VERTEX_COLORS
#if defined(COLOR_SRGB)
    v_color = vec4(srgb_to_linear(c.rgb), c.a);
#else
    v_color = c;
#endif
#endif
}
