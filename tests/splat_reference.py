"""The reference forward pass of 3D Gaussian Splatting (Kerbl et al. 2023, its CUDA
rasterizer's preprocessCUDA, computeCov2D, computeColorFromSH and renderCUDA) transcribed
to numpy, as the oracle of facet's splats (tests/test_splats.py). Independent of facet's
code: its own SH constants, covariance, projection and compositing. Camera in OpenCV axes
(x right, y down, z forward) with pinhole intrinsics in OpenCV's convention (pixel (i, j)'s
centre at (i, j), as the reference's ndc2Pix). Where facet departs from the reference
(facet.render.raster.splats): the pixels a splat reaches are its 3-sigma box here too (not
whole 16-pixel tiles), a splat nearer than ``near`` is left out (the reference: 0.2)."""

from __future__ import annotations

import numpy as np

C0 = 0.28209479177387814
C1 = 0.4886025119029199
C2 = [1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792,
      0.5462742152960396]
C3 = [-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
      -0.4570457994644658, 1.445305721320277, -0.5900435899266435]


def sh_color(sh, d):
    """computeColorFromSH: sh (K, 3), d a unit direction (3,): RGB + 0.5 clamped at 0."""
    x, y, z = d
    k = sh.shape[0]
    r = C0 * sh[0]
    if k > 1:
        r = r - C1 * y * sh[1] + C1 * z * sh[2] - C1 * x * sh[3]
    if k > 4:
        xx, yy, zz, xy, yz, xz = x * x, y * y, z * z, x * y, y * z, x * z
        r = (r + C2[0] * xy * sh[4] + C2[1] * yz * sh[5] + C2[2] * (2 * zz - xx - yy) * sh[6]
             + C2[3] * xz * sh[7] + C2[4] * (xx - yy) * sh[8])
    if k > 9:
        r = (r + C3[0] * y * (3 * xx - yy) * sh[9] + C3[1] * xy * z * sh[10]
             + C3[2] * y * (4 * zz - xx - yy) * sh[11]
             + C3[3] * z * (2 * zz - 3 * xx - 3 * yy) * sh[12]
             + C3[4] * x * (4 * zz - xx - yy) * sh[13] + C3[5] * z * (xx - yy) * sh[14]
             + C3[6] * x * (xx - 3 * yy) * sh[15])
    return np.maximum(r + 0.5, 0.0)


def rotation(q):
    w, x, y, z = np.asarray(q, np.float64) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def render(means, scales, quats, opacities, sh, world_to_cv, K, width, height,
           background=(0.0, 0.0, 0.0), near=0.2):
    """(H, W, 3) float64 image, row 0 at the top (the reference's renderCUDA)."""
    covs = []
    for i in range(len(means)):
        M = rotation(quats[i]) @ np.diag(scales[i])
        covs.append(M @ M.T)
    return render_covariances(means, covs, opacities, sh, world_to_cv, K, width, height,
                              background, near)


def render_covariances(means, covs, opacities, sh, world_to_cv, K, width, height,
                       background=(0.0, 0.0, 0.0), near=0.2, to_local=None):
    """``render`` of splats given by world covariances; ``to_local``: the 3x3 map of view
    directions into the splats' own frame (a placed cloud's SH turns with it)."""
    fx, fy, cx, cy = K[0][0], K[1][1], K[0][2], K[1][2]
    tan_x, tan_y = width / (2 * fx), height / (2 * fy)
    R, t_cam = np.asarray(world_to_cv)[:3, :3], np.asarray(world_to_cv)[:3, 3]
    eye = -R.T @ t_cam
    items = []
    for i in range(len(means)):
        t = R @ means[i] + t_cam
        if t[2] <= near:
            continue
        sigma = np.asarray(covs[i], np.float64)
        lim_x, lim_y = 1.3 * tan_x, 1.3 * tan_y
        tx = np.clip(t[0] / t[2], -lim_x, lim_x) * t[2]
        ty = np.clip(t[1] / t[2], -lim_y, lim_y) * t[2]
        J = np.array([[fx / t[2], 0, -fx * tx / t[2] ** 2],
                      [0, fy / t[2], -fy * ty / t[2] ** 2]])
        T = J @ R
        cov = T @ sigma @ T.T
        a, b, c = cov[0, 0] + 0.3, cov[0, 1], cov[1, 1] + 0.3
        det = a * c - b * b
        if det <= 0:
            continue
        conic = np.array([c, -b, a]) / det
        mid = 0.5 * (a + c)
        lam = mid + np.sqrt(max(0.1, mid * mid - det))
        radius = np.ceil(3.0 * np.sqrt(lam))
        u, v = fx * t[0] / t[2] + cx, fy * t[1] / t[2] + cy
        d = means[i] - eye
        if to_local is not None:
            d = np.asarray(to_local) @ d
        color = sh_color(np.asarray(sh[i], np.float64), d / np.linalg.norm(d))
        items.append((t[2], u, v, conic, radius, float(opacities[i]), color))
    items.sort(key=lambda it: it[0])
    C = np.zeros((height, width, 3))
    T = np.ones((height, width))
    done = np.zeros((height, width), bool)
    px, py = np.meshgrid(np.arange(width, dtype=np.float64), np.arange(height, dtype=np.float64))
    for _, u, v, conic, radius, opacity, color in items:
        box = (np.abs(px - u) <= radius) & (np.abs(py - v) <= radius) & ~done
        if not box.any():
            continue
        dx, dy = u - px[box], v - py[box]
        power = -0.5 * (conic[0] * dx * dx + conic[2] * dy * dy) - conic[1] * dx * dy
        alpha = np.minimum(0.99, opacity * np.exp(power))
        use = (power <= 0) & (alpha >= 1.0 / 255.0)
        t_now = T[box]
        test = t_now * (1 - alpha)
        stop = use & (test < 1e-4)
        add = use & ~stop
        rows, cols = np.nonzero(box)
        C[rows[add], cols[add]] += (alpha[add] * t_now[add])[:, None] * color
        T[rows[add], cols[add]] = test[add]
        done[rows[stop], cols[stop]] = True
    return C + T[..., None] * np.asarray(background, np.float64)
