#version 330 core
// One Gaussian splat as a screen-space quad (facet.render.raster.splats), as the reference
// forward pass of 3D Gaussian Splatting projects it: the covariance carried into view space
// and through the projection's Jacobian at the mean (its x/z and y/z clamped to 1.3 times
// the half field of view first; any projection: the Jacobian is d(pixels)/d(view point) of
// u_projection, orthographic included), 0.3 px^2 added on the diagonal, the quad reaching
// ceil(3 sqrt(largest eigenvalue)) pixels from the mean's pixel.
layout(location = 0) in vec2 a_corner;  // (-1, -1) ... (1, 1)
in vec3 a_mean;                         // world
in vec3 a_cov_a;                        // world covariance: xx, xy, xz
in vec3 a_cov_b;                        //                   yy, yz, zz
in vec4 a_color;                        // rgb (display values), opacity
in float a_id;                          // the cloud's object id + 1

uniform mat4 u_view;        // world -> view (OpenGL axes)
uniform mat4 u_projection;  // view -> clip, as the frame's (jittered, flipped)
uniform vec2 u_viewport;    // pixels

flat out vec3 v_conic;      // the inverse 2D covariance (xx, xy, yy), pixels^-2
flat out vec4 v_color;
flat out vec2 v_center;     // the mean in window pixels
flat out float v_depth;     // along the camera axis
flat out float v_id;

const float DILATION = 0.3;  // px^2 on the 2D covariance's diagonal (the reference's)
const float CLAMP = 1.3;     // x/z and y/z at most this times the half field of view

vec3 jacobian_row(vec4 c, int r) {  // d(ndc[r]) / d(view point), at clip point c
    vec3 p = vec3(u_projection[0][r], u_projection[1][r], u_projection[2][r]);
    vec3 w = vec3(u_projection[0][3], u_projection[1][3], u_projection[2][3]);
    return (p * c.w - c[r] * w) / (c.w * c.w);
}

void main() {
    vec4 t = u_view * vec4(a_mean, 1.0);
    vec4 clip = u_projection * t;
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // (culled: outside the clip volume)
    if (clip.w <= 0.0 || abs(clip.z) > clip.w) return;  // behind the camera, or past near/far
    vec2 ndc = clip.xy / clip.w;
    // The reference's clamp: the Jacobian is taken at the mean pulled in to 1.3 times the
    // field of view (a splat far outside the view is not stretched without bound).
    vec2 pulled = clamp(ndc, -CLAMP, CLAMP);
    vec4 tj = t;
    if (u_projection[2][3] != 0.0 && pulled != ndc) {  // perspective: solve for x, y
        float w = clip.w;
        tj.x = (pulled.x * w - u_projection[2][0] * t.z - u_projection[3][0]) / u_projection[0][0];
        tj.y = (pulled.y * w - u_projection[2][1] * t.z - u_projection[3][1]) / u_projection[1][1];
    }
    vec4 cj = u_projection * tj;
    vec3 j0 = jacobian_row(cj, 0) * 0.5 * u_viewport.x;
    vec3 j1 = jacobian_row(cj, 1) * 0.5 * u_viewport.y;
    mat3 W = mat3(u_view);
    mat3 S = mat3(a_cov_a.x, a_cov_a.y, a_cov_a.z,
                  a_cov_a.y, a_cov_b.x, a_cov_b.y,
                  a_cov_a.z, a_cov_b.y, a_cov_b.z);
    vec3 r0 = transpose(W) * j0, r1 = transpose(W) * j1;  // rows of J W
    float a = dot(r0, S * r0) + DILATION;
    float b = dot(r0, S * r1);
    float c = dot(r1, S * r1) + DILATION;
    float det = a * c - b * b;
    if (det <= 0.0) return;
    float mid = 0.5 * (a + c);
    float lambda = mid + sqrt(max(0.1, mid * mid - det));
    float radius = ceil(3.0 * sqrt(lambda));
    v_conic = vec3(c, -b, a) / det;
    v_center = (ndc * 0.5 + 0.5) * u_viewport;
    v_color = a_color;
    v_depth = -t.z;
    v_id = a_id;
    vec2 corner = v_center + a_corner * radius;
    gl_Position = vec4(corner / u_viewport * 2.0 - 1.0, clip.z / clip.w, 1.0);
}
