"""Deterministic generated triangle meshes for self-collision tests.

``all_cases()`` returns a list of ``(name, faces, V)`` with faces an int64
array (m, 3) and V a float64 array (n, 3).  ``case(name)`` fetches one.
Everything is built from fixed seeds, so the output is bit-for-bit
reproducible (only numpy float64 arithmetic + np.random.default_rng).

Grid coordinates are dyadic (multiples of powers of two) wherever exactness
matters (exact flat folds, exact midpoints, duplicated positions).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["all_cases", "case", "case_names"]


# ---------------------------------------------------------------------------
# primitive builders
# ---------------------------------------------------------------------------

def grid(nx, ny, hx=0.125, hy=0.125, x0=0.0, y0=0.0, alt=False):
    """Flat grid in z=0 of nx*ny quads (2*nx*ny triangles, normals +z).

    Vertex (i, j) has index j*(nx+1)+i and position (x0+i*hx, y0+j*hy, 0).
    alt=True alternates the quad diagonal in a checkerboard pattern.
    """
    xs = x0 + np.arange(nx + 1) * hx
    ys = y0 + np.arange(ny + 1) * hy
    X, Y = np.meshgrid(xs, ys)
    V = np.stack([X.ravel(), Y.ravel(), np.zeros(X.size)], axis=1)
    F = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            b = a + 1
            c = a + nx + 2
            d = a + nx + 1
            if alt and (i + j) % 2:
                F += [(a, b, d), (b, c, d)]
            else:
                F += [(a, b, c), (a, c, d)]
    return np.array(F, dtype=np.int64), V.astype(np.float64)


def cylinder(nu, nv, r=1.0, height=2.0):
    """Open cylinder around z, nu segments around, nv rows; outward normals."""
    V = []
    for j in range(nv + 1):
        z = height * j / nv
        for i in range(nu):
            a = 2.0 * math.pi * i / nu
            V.append((r * math.cos(a), r * math.sin(a), z))
    F = []
    for j in range(nv):
        for i in range(nu):
            a = j * nu + i
            b = j * nu + (i + 1) % nu
            c = b + nu
            d = a + nu
            F += [(a, b, c), (a, c, d)]
    return np.array(F, dtype=np.int64), np.array(V, dtype=np.float64)


def uv_sphere(nu, nv, r=1.0):
    """UV sphere with poles; nu longitudes, nv latitude bands; outward normals."""
    V = [(0.0, 0.0, -r)]
    for j in range(1, nv):
        th = math.pi * j / nv
        z = -r * math.cos(th)
        s = r * math.sin(th)
        for i in range(nu):
            a = 2.0 * math.pi * i / nu
            V.append((s * math.cos(a), s * math.sin(a), z))
    V.append((0.0, 0.0, r))
    top = len(V) - 1

    def ring(j, i):
        return 1 + (j - 1) * nu + (i % nu)

    F = []
    for i in range(nu):
        F.append((0, ring(1, i + 1), ring(1, i)))
    for j in range(1, nv - 1):
        for i in range(nu):
            a, b = ring(j, i), ring(j, i + 1)
            c, d = ring(j + 1, i + 1), ring(j + 1, i)
            F += [(a, b, c), (a, c, d)]
    for i in range(nu):
        F.append((top, ring(nv - 1, i), ring(nv - 1, i + 1)))
    return np.array(F, dtype=np.int64), np.array(V, dtype=np.float64)


def combine(*parts):
    """Concatenate (faces, V) meshes into one (indices re-based)."""
    Fs, Vs, off = [], [], 0
    for F, V in parts:
        Fs.append(np.asarray(F, dtype=np.int64) + off)
        Vs.append(np.asarray(V, dtype=np.float64))
        off += len(V)
    return np.concatenate(Fs), np.concatenate(Vs)


def compact(F, V):
    """Drop unreferenced vertices (keeps order)."""
    used = np.unique(F)
    remap = -np.ones(len(V), dtype=np.int64)
    remap[used] = np.arange(len(used))
    return remap[F], V[used].copy()


# ---------------------------------------------------------------------------
# deformations
# ---------------------------------------------------------------------------

def _rot_about_y_line(P, xf, theta):
    """Rotate points (x, z) about the line x = xf, z = 0 (direction +y)."""
    c, s = math.cos(theta), math.sin(theta)
    d = P[:, 0] - xf
    z = P[:, 2]
    out = P.copy()
    out[:, 0] = xf + d * c - z * s
    out[:, 2] = d * s + z * c
    return out


def fold_x(V, V_ref, xf, deg, ramp=None):
    """Fold: vertices whose reference x > xf rotate by deg about x = xf.

    ``V_ref`` (the flat reference positions) decides which side a vertex is on,
    so folds compose.  With ``ramp=(y0, y1)`` the angle ramps linearly from 0
    at y <= y0 to deg at y >= y1 (a twisted fold).
    """
    V = V.copy()
    sel = V_ref[:, 0] > xf
    if ramp is None:
        V[sel] = _rot_about_y_line(V[sel], xf, math.radians(deg))
        return V
    y0, y1 = ramp
    for k in np.nonzero(sel)[0]:
        y = V_ref[k, 1]
        f = min(1.0, max(0.0, (y - y0) / (y1 - y0)))
        V[k] = _rot_about_y_line(V[k:k + 1], xf, math.radians(deg * f))[0]
    return V


def fold_y(V, V_ref, yf, deg):
    """Fold about the line y = yf (direction +x), using current z and y."""
    Vs = V[:, [1, 0, 2]]
    Rs = V_ref[:, [1, 0, 2]]
    out = fold_x(Vs, Rs, yf, deg)
    return out[:, [1, 0, 2]]


def mirror_fold_exact(V, xf):
    """Exact 180 degree fold: x -> 2*xf - x for x > xf (z untouched)."""
    V = V.copy()
    sel = V[:, 0] > xf
    V[sel, 0] = 2.0 * xf - V[sel, 0]
    return V


def smooth_field(P, rng, n_modes, amp, freq):
    """Sum of random sinusoids R^3 -> R^3, evaluated at points P."""
    out = np.zeros_like(P)
    for _ in range(n_modes):
        k = rng.normal(size=3) * freq
        ph = rng.uniform(0, 2 * math.pi)
        a = rng.normal(size=3) * amp
        out += np.sin(P @ k + ph)[:, None] * a[None, :]
    return out


def twist_z(V, rate):
    """Rotate each vertex about the z axis by rate * z (radians)."""
    a = rate * V[:, 2]
    c, s = np.cos(a), np.sin(a)
    out = V.copy()
    out[:, 0] = c * V[:, 0] - s * V[:, 1]
    out[:, 1] = s * V[:, 0] + c * V[:, 1]
    return out


def rot_x(V, deg):
    t = math.radians(deg)
    c, s = math.cos(t), math.sin(t)
    out = V.copy()
    out[:, 1] = c * V[:, 1] - s * V[:, 2]
    out[:, 2] = s * V[:, 1] + c * V[:, 2]
    return out


def rot_axis(V, axis, deg, center=(0.0, 0.0, 0.0)):
    """Rodrigues rotation of points about an axis through center."""
    k = np.asarray(axis, dtype=np.float64)
    k = k / np.linalg.norm(k)
    t = math.radians(deg)
    P = V - np.asarray(center)
    out = (P * math.cos(t) + np.cross(k, P) * math.sin(t)
           + np.outer(P @ k, k) * (1 - math.cos(t)))
    return out + np.asarray(center)


# ---------------------------------------------------------------------------
# case families
# ---------------------------------------------------------------------------

def _folds():
    out = []
    # single folds below 180: clean, no collisions
    for deg, n in ((90, 10), (150, 12), (179, 10)):
        F, V = grid(n, n)
        xf = 0.125 * (n // 2)
        out.append((f"fold_single_{deg:03d}_g{n}", F, fold_x(V, V, xf, deg)))
    # float 180 fold: cos = -1 exactly, sin ~ 1.2e-16 -> flap hovers a hair
    # above the base (near coplanar, still no collision)
    F, V = grid(10, 8, alt=True)
    out.append(("fold_single_180_float_hover", F, fold_x(V, V, 0.625, 180)))
    # single fold past 180 with a planar sheet: no intersection (hard negative)
    F, V = grid(10, 10)
    out.append(("fold_single_200_planar_nocross", F, fold_x(V, V, 0.625, 200)))
    # Z folds: fold past 180 and fold the tip back up through the base
    for deg, back, n in ((190, -90, 12), (200, -100, 14),
                         (240, -150, 12), (270, -135, 16)):
        F, V = grid(n, 6, hy=0.25)
        x1 = 0.125 * (n * 5 // 8)
        x2 = x1 + 0.125 * 2
        W = fold_x(V, V, x2, back)
        W = fold_x(W, V, x1, deg)
        out.append((f"fold_zfold_{deg:03d}_back{-back:03d}_g{n}", F, W))
    # twisted fold: fold angle ramps 0 -> deg along y, crosses 180 on the way
    for deg, n in ((220, 12), (300, 10)):
        F, V = grid(n, n)
        W = fold_x(V, V, 0.125 * (n // 2), deg, ramp=(0.2, 1.0))
        out.append((f"fold_twisted_ramp_{deg:03d}_g{n}", F, W))
    # double fold: 160 deg about x = 0.75, then the half y > 0.75 (base and
    # flap together) is turned 200 deg about the line y = 0.75, z = 0; the
    # flap faces at the second crease get stretched, the layers cross
    F, V = grid(12, 12)
    W = fold_x(V, V, 0.75, 160)
    W = fold_y(W, V, 0.75, 200)
    out.append(("fold_double_x160_y200", F, W))
    # exact flat folds: mirror x about a grid line, all z = 0
    for nx, ny, k, alt in ((10, 10, 5, False), (9, 7, 3, True), (12, 8, 8, False)):
        F, V = grid(nx, ny, alt=alt)
        W = mirror_fold_exact(V, 0.125 * k)
        out.append((f"fold_flat_exact_g{nx}x{ny}_at{k}", F, W))
    return out


def _crumples():
    out = []
    specs = [
        # name, n, seed, amp (smooth), freq, noise
        ("crumple_mild_s0", 12, 10, 0.02, 3.0, 0.0),
        ("crumple_mild_s1", 14, 11, 0.03, 2.0, 0.002),
        ("crumple_medium_s2", 12, 12, 0.12, 6.0, 0.01),
        ("crumple_strong_s3", 12, 13, 0.25, 9.0, 0.02),
        ("crumple_strong_s4", 10, 14, 0.35, 12.0, 0.0),
        ("crumple_noisy_s5", 10, 15, 0.05, 4.0, 0.09),
    ]
    for name, n, seed, amp, freq, noise in specs:
        rng = np.random.default_rng(seed)
        F, V = grid(n, n, alt=(seed % 2 == 0))
        W = V + smooth_field(V, rng, 6, amp, freq)
        if noise:
            W = W + rng.normal(size=W.shape) * noise
        out.append((name, F, W))
    # gently bent sheets: no collisions
    F, V = grid(14, 10)
    W = V.copy()
    W[:, 2] = 0.3 * (V[:, 0] - 0.8) ** 2
    out.append(("bent_sheet_parabola", F, W))
    F, V = grid(16, 6, hy=0.25)
    W = V.copy()
    ang = V[:, 0] / 2.0 * (1.5 * math.pi)  # roll 270 degrees: still clean
    W[:, 0] = 0.5 * np.sin(ang)
    W[:, 2] = 0.5 * (1 - np.cos(ang))
    out.append(("bent_sheet_roll_270", F, W))
    # rolled past 360 degrees at constant radius: layers cross
    F, V = grid(24, 5, hy=0.25)
    W = V.copy()
    ang = V[:, 0] / 3.0 * math.radians(420)
    W[:, 0] = 0.5 * np.sin(ang)
    W[:, 2] = 0.5 * (1 - np.cos(ang))
    out.append(("sheet_rolled_420", F, W))
    return out


def _tubes():
    out = []
    F, V = cylinder(16, 8)
    out.append(("cylinder_plain_16x8", F, V))
    out.append(("cylinder_twist_mild", F, twist_z(V, 0.4)))
    F2, V2 = cylinder(20, 6, height=1.0)
    # 1.6 turns: long skewed chords, still clean; 2.7 turns: 162 deg per row,
    # the chord triangles pass through the axis and interleave
    out.append(("cylinder_twist_steep_clean", F2, twist_z(V2, 2.0 * math.pi * 1.6)))
    out.append(("cylinder_twist_strong", F2, twist_z(V2, 2.0 * math.pi * 2.7)))
    rng = np.random.default_rng(21)
    out.append(("cylinder_noise_mild", F, V + rng.normal(size=V.shape) * 0.01))
    rng = np.random.default_rng(22)
    out.append(("cylinder_noise_strong", F, V + rng.normal(size=V.shape) * 0.2))
    rng = np.random.default_rng(23)
    W = twist_z(V, 1.2) + rng.normal(size=V.shape) * 0.05
    out.append(("cylinder_twist_noise", F, W))
    # squashed cylinder: the two walls pushed through each other
    W = V.copy()
    # top wall (y > 0) pushed to y < 0 and bottom wall to y > 0
    # flatten the tube with an x-dependent sign flip: the two walls cross
    # each other along x ~ 0.51 and x ~ -0.75
    W[:, 1] = V[:, 1] * np.cos(2.5 * V[:, 0] + 0.3) * 0.5
    out.append(("cylinder_squashed_through", F, W))

    F, V = uv_sphere(16, 10)
    out.append(("sphere_plain_16x10", F, V))
    out.append(("sphere_twist_mild", F, twist_z(V, 0.8)))
    out.append(("sphere_twist_steep_clean", F, twist_z(V, 6.0)))
    out.append(("sphere_twist_strong", F, twist_z(V, 9.0)))
    rng = np.random.default_rng(31)
    out.append(("sphere_noise_mild", F, V * (1 + rng.normal(size=(len(V), 1)) * 0.01)))
    rng = np.random.default_rng(32)
    out.append(("sphere_noise_strong", F, V + rng.normal(size=V.shape) * 0.15))
    F, V = uv_sphere(12, 8)
    W = V.copy()
    s2 = V[:, 0] ** 2 + V[:, 1] ** 2
    W[:, 2] = np.where(V[:, 2] > 0, V[:, 2] - 2.2 * np.exp(-4.0 * s2), V[:, 2])
    out.append(("sphere_pole_pushed_through", F, W))
    W = V.copy()
    W[:, 2] = np.where(V[:, 2] > 0, V[:, 2] - 0.8 * np.exp(-4.0 * s2), V[:, 2])
    out.append(("sphere_pole_dented", F, W))
    return out


def _holes_components():
    out = []
    # grid with holes
    F, V = grid(12, 12)
    keep = np.ones(len(F), dtype=bool)
    for q in ((3, 3), (3, 4), (4, 3), (4, 4), (8, 7), (8, 8), (2, 9)):
        qi = q[1] * 12 + q[0]
        keep[2 * qi] = keep[2 * qi + 1] = False
    keep[2 * (6 * 12 + 6)] = False  # a single missing triangle
    Fh = F[keep]
    Fh, Vh = compact(Fh, V)
    out.append(("holes_flat", Fh, Vh))
    Wz = Vh.copy()
    Wz[:, 2] = 0.2 * np.sin(3 * Vh[:, 0]) * np.cos(2 * Vh[:, 1])
    out.append(("holes_wavy", Fh, Wz))
    # Z fold of a holey strip
    F, V = grid(14, 6, hy=0.25)
    keep = np.ones(len(F), dtype=bool)
    for qi in (2 * 14 + 3, 2 * 14 + 4, 3 * 14 + 10, 1 * 14 + 12):
        keep[2 * qi] = keep[2 * qi + 1] = False
    Fh, Vh = compact(F[keep], V)
    W = fold_x(Vh, Vh, 0.125 * 11, -100)
    W = fold_x(W, Vh, 0.125 * 9, 200)
    out.append(("holes_zfold_200", Fh, W))
    rng = np.random.default_rng(41)
    out.append(("holes_crumpled", Fh, Vh + smooth_field(Vh, rng, 6, 0.3, 10.0)))

    # several components
    A = grid(8, 8)
    B = grid(8, 8)
    BV = B[1].copy()
    BV[:, 2] = 0.5
    out.append(("components_two_parallel", *combine(A, (B[0], BV))))
    BV = rot_x(B[1] - np.array([0.0, 0.5, 0.0]), 30.0) + np.array([0.3, 0.5, 0.0])
    out.append(("components_two_interpenetrating", *combine(A, (B[0], BV))))
    # three sheets: two parallel, a third crossing both
    C = grid(6, 10, hx=0.125, hy=0.125)
    CV = C[1][:, [2, 1, 0]] + np.array([0.4, -0.1, -0.3])  # vertical plane x=0.4
    AV2 = A[1].copy()
    AV2[:, 2] = 0.4
    out.append(("components_three_crossing", *combine(A, (A[0], AV2), (C[0], CV))))
    # sheet crossing through another, perpendicular, off-grid offsets
    D = grid(10, 6, hx=0.1, hy=0.1)
    DV = D[1][:, [0, 2, 1]] + np.array([-0.07, 0.4375 + 0.01, -0.23])
    out.append(("components_sheet_pierces_sheet", *combine(A, (D[0], DV))))
    # coplanar overlaps (same z)
    BV = B[1] + np.array([0.3, 0.17, 0.0])
    out.append(("components_coplanar_overlap_offset", *combine(A, (B[0], BV))))
    BV = B[1] + np.array([0.375, 0.25, 0.0])  # grid-aligned: duplicated positions
    out.append(("components_coplanar_overlap_aligned", *combine(A, (B[0], BV))))
    BV = rot_axis(B[1], (0, 0, 1), 33.0, center=(0.5, 0.5, 0.0))
    BV[:, 2] = 0.0
    out.append(("components_coplanar_overlap_rotated", *combine(A, (B[0], BV))))
    return out


def _fans():
    out = []

    def fan(n, a0, a1, closed=False, z=None, center=(0.0, 0.0, 0.0), r=1.0):
        """Center + rim fan; returns faces, V (center index 0)."""
        V = [center]
        m = n if closed else n + 1
        for k in range(m):
            a = a0 + (a1 - a0) * k / n
            zz = 0.0 if z is None else z(k)
            V.append((center[0] + r * math.cos(a), center[1] + r * math.sin(a),
                      center[2] + zz))
        F = []
        for k in range(n):
            b = 1 + k
            c = 1 + ((k + 1) % m)
            F.append((0, b, c))
        return np.array(F, dtype=np.int64), np.array(V, dtype=np.float64)

    def wedge_tri(alpha, half, tilt, r=0.9):
        """Triangle (c, p, q) spanning [alpha-half, alpha+half] in z=0,
        rotated by tilt degrees about its bisector ray (through the origin)."""
        P = np.array([[0.0, 0.0, 0.0],
                      [r * math.cos(alpha - half), r * math.sin(alpha - half), 0.0],
                      [r * math.cos(alpha + half), r * math.sin(alpha + half), 0.0]])
        P = rot_axis(P, (math.cos(alpha), math.sin(alpha), 0.0), tilt)
        P[0] = 0.0
        return P

    # open fan over 0..250 deg + a lone triangle sharing only the centre
    for tag, alpha, tilt in (("through", math.radians(70), 90.0),
                             ("through_shallow", math.radians(130), 12.0),
                             ("outside", math.radians(305), 60.0)):
        F, V = fan(5, 0.0, math.radians(250))
        T = wedge_tri(alpha, math.radians(20), tilt)
        V2 = np.concatenate([V, T[1:]])
        F2 = np.concatenate([F, np.array([[0, len(V), len(V) + 1]])])
        out.append((f"fan_vertex_fold_{tag}", F2, V2))
    # closed fan where one rim vertex is pushed through the neighbour wedge
    F, V = fan(8, 0.0, 2 * math.pi, closed=True)
    V = V.copy()
    V[3] = (0.6 * math.cos(math.radians(20)), 0.6 * math.sin(math.radians(20)), 0.3)
    V[4] = (0.7 * math.cos(math.radians(60)), 0.7 * math.sin(math.radians(60)), -0.3)
    out.append(("fan_closed_rim_pushed_through", F, V))

    # edge-sharing pair folded coplanar onto itself (same side)
    V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.25, 0.75, 0.0], [0.625, 0.5, 0.0]])
    out.append(("edge_pair_foldover_coplanar", np.array([[0, 1, 2], [1, 0, 3]]), V))
    # same pair folded to opposite sides (clean) for contrast, in a small strip
    V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.25, 0.75, 0.0], [0.625, -0.5, 0.0]])
    out.append(("edge_pair_flat_opposite", np.array([[0, 1, 2], [1, 0, 3]]), V))
    # grid corner triangle folded over its diagonal neighbour (exactly onto it)
    for nx, hx, hy in ((8, 0.125, 0.125), (9, 0.125, 0.0625)):
        F, V = grid(nx, 6, hx=hx, hy=hy)
        V = V.copy()
        corner = nx  # vertex (nx, 0): only in triangle (v00, v10, v11)
        a = V[corner - 1]
        c = V[corner + nx + 1]
        u = c - a
        p = V[corner] - a
        V[corner] = a + 2.0 * (p @ u) / (u @ u) * u - p
        V[corner, 2] = 0.0
        out.append((f"grid_corner_foldover_{nx}x6_h{hx}_{hy}", F, V))

    # ring winding twice around the centre
    n = 12

    def ang(k):
        return 2 * math.pi * (k % (n // 2)) / (n // 2)

    Vf = [(0.0, 0.0, 0.0)] + [(math.cos(ang(k)), math.sin(ang(k)), 0.0) for k in range(n)]
    Ff = [(0, 1 + k, 1 + (k + 1) % n) for k in range(n)]
    out.append(("fan_ring_winds_twice_flat", np.array(Ff), np.array(Vf)))
    Vh = [(0.0, 0.0, 0.0)] + [(math.cos(ang(k)), math.sin(ang(k)), 0.0625 * k)
                              for k in range(n)]
    # the closing face (0, n, 1) jumps back down; it's part of the ring too
    out.append(("fan_ring_winds_twice_helix", np.array(Ff), np.array(Vh)))
    # without the closing face the helical fan is clean
    out.append(("fan_ring_winds_twice_helix_open", np.array(Ff[:-1]), np.array(Vh)))
    Vh2 = [(0.0, 0.0, 0.0)] + [(math.cos(ang(k)), math.sin(ang(k)),
                                0.0625 * (k if k < n // 2 else n - k)) for k in range(n)]
    out.append(("fan_ring_winds_twice_updown_dup", np.array(Ff), np.array(Vh2)))
    return out


def _nonmanifold():
    out = []
    # fins: several triangles on one sheet edge (clean)
    F, V = grid(10, 10)
    a = 5 * 11 + 4
    b = a + 1  # edge (a, b) lies on grid line y = 5*h
    extra_V = [(0.5625, 0.625, 0.5), (0.5625, 0.5, 0.5),     # up, tilted
               (0.5625, 0.625, -0.4), (0.5625, 0.75, 0.3)]  # down, tilted
    Vx = np.concatenate([V, np.array(extra_V)])
    Fx = np.concatenate([F, np.array([[a, b, 121 + k] for k in range(4)])])
    out.append(("fins_four_on_one_edge", Fx, Vx))
    # two fins on the same edge, coplanar and on the same side -> overlap
    # (plane z = y - 0.625 contains the edge and both apexes)
    extra_V = [(0.53125, 1.125, 0.5), (0.53125, 0.875, 0.25)]
    Vx = np.concatenate([V, np.array(extra_V)])
    Fx = np.concatenate([F, np.array([[a, b, 121], [b, a, 122]])])
    out.append(("fins_coplanar_overlap", Fx, Vx))
    # fin strip standing on a grid line + folded flap passing through it
    n = 12
    F, V = grid(n, 6, hy=0.125)
    line_i = 4  # vertices with i == 4
    base = [j * (n + 1) + line_i for j in range(7)]
    top = [len(V) + j for j in range(7)]
    TV = V[base].copy()
    TV[:, 2] = 0.6
    fins = []
    for j in range(6):
        fins += [(base[j], base[j + 1], top[j + 1]), (base[j], top[j + 1], top[j])]
    Fall = np.concatenate([F, np.array(fins)])
    Vall = np.concatenate([V, TV])
    out.append(("fins_strip_clean", Fall, Vall))
    W = fold_x(Vall, Vall, 0.125 * 6, 125.0)
    W[len(V):] = TV  # the fin stays put
    out.append(("fins_strip_pierced_by_flap", Fall, W))

    # bowties: two fans sharing only the centre vertex
    def fan_loc(n, a0, a1, z=0.0, closed=False):
        """Fan around the origin (index 0); closed=True for a full disc."""
        m = n if closed else n + 1
        Vloc = [(0.0, 0.0, 0.0)]
        for k in range(m):
            a = a0 + (a1 - a0) * k / n
            Vloc.append((math.cos(a), math.sin(a), z))
        Floc = [(0, 1 + k, 1 + (k + 1) % m) for k in range(n)]
        return np.array(Floc, dtype=np.int64), np.array(Vloc)

    def bowtie(F1, V1, F2, V2, share=True):
        Fb = np.concatenate([F1, F2 + len(V1)])
        if share:
            Fb[Fb == len(V1)] = 0  # second centre -> first centre index
        return compact(Fb, np.concatenate([V1, V2]))

    F1, V1 = fan_loc(4, math.radians(100), math.radians(260))
    F2, V2 = fan_loc(4, math.radians(-80), math.radians(80))
    out.append(("bowtie_flat_clean", *bowtie(F1, V1, F2, V2)))
    # double cone (clean), and the same with distinct apex indices (touching)
    F1, V1 = fan_loc(6, 0.0, 2 * math.pi, z=0.7, closed=True)
    F2, V2 = fan_loc(6, 0.0, 2 * math.pi, z=-0.7, closed=True)
    out.append(("bowtie_double_cone_clean", *bowtie(F1, V1, F2, V2)))
    out.append(("bowtie_double_cone_dup_apex", *bowtie(F1, V1, F2, V2, share=False)))
    # two full discs in perpendicular planes sharing the centre: they cross
    F1, V1 = fan_loc(7, 0.1, 0.1 + 2 * math.pi, closed=True)
    V2 = V1[:, [2, 0, 1]]  # disc in the plane x = 0
    out.append(("bowtie_crossing_discs", *bowtie(F1, V1, F1, V2)))
    # two half fans on the same side, one tilted 25 deg about the -x axis:
    # they cross along a segment of the -x axis
    F1, V1 = fan_loc(3, math.radians(110), math.radians(250))
    F2, V2 = fan_loc(3, math.radians(125), math.radians(235))
    V2 = rot_axis(V2, (-1.0, 0.0, 0.0), 25.0)
    out.append(("bowtie_tilted_into_each_other", *bowtie(F1, V1, F2, V2)))
    return out


def _numerics():
    out = []
    off = np.array([1e6, -1e6, 1e6])
    F, V = grid(12, 6, hy=0.25)
    W = fold_x(V, V, 0.125 * 9, -100)
    W = fold_x(W, V, 0.125 * 7, 200)
    out.append(("offset_1e6_zfold_200", F, W + off))
    F, V = grid(10, 10)
    out.append(("offset_1e6_flat_exact_fold", F, mirror_fold_exact(V, 0.625) + off))
    out.append(("offset_1e6_fold_150_clean", F, fold_x(V, V, 0.625, 150) + off))
    rng = np.random.default_rng(51)
    F, V = grid(10, 10, alt=True)
    out.append(("offset_1e6_crumpled", F, V + smooth_field(V, rng, 6, 0.3, 10.0) + off))

    # slivers: vertex moved exactly onto the midpoint of the opposite edge
    F, V = grid(10, 10)
    W = V.copy()
    W[:, 2] = 0.25 * (V[:, 0] - 0.5) ** 2 + 0.125 * V[:, 1] ** 2
    out_flat = V.copy()
    for (i, j) in ((3, 3), (6, 7), (8, 2)):
        # face (a, b, c) of quad (i, j) with a=(i,j), b=(i+1,j), c=(i+1,j+1)
        a = j * 11 + i
        c = a + 12
        b = a + 1
        out_flat[b] = 0.5 * (out_flat[a] + out_flat[c])  # b onto the diagonal
    out.append(("sliver_midpoint_flat", F, out_flat))
    Wb = W.copy()
    for (i, j) in ((3, 3), (6, 7), (8, 2)):
        a = j * 11 + i
        b = a + 1
        c = a + 12
        Wb[b] = 0.5 * (Wb[a] + Wb[c])
    out.append(("sliver_midpoint_bent", F, Wb))
    # zero-area faces: a face collapsed to a point / to a segment with a
    # duplicated position, on a bent sheet
    Wc = W.copy()
    a = 4 * 11 + 4
    Wc[a + 1] = Wc[a]            # edge (a, a+1) collapsed: segment triangle
    q = 7 * 11 + 6
    Wc[q + 1] = Wc[q]
    Wc[q + 12] = Wc[q]           # face (q, q+1, q+12) collapsed to a point
    out.append(("degenerate_collapsed_faces_bent", F, Wc))
    # duplicated positions: a sheet cut along a seam, both halves touching
    F, V = grid(10, 8)
    Fl = F[(np.arange(len(F)) // 2) % 10 < 5]
    Fr = F[(np.arange(len(F)) // 2) % 10 >= 5]
    Fr2 = Fr + len(V)
    Fs, Vs = compact(np.concatenate([Fl, Fr2]), np.concatenate([V, V]))
    out.append(("duplicate_seam_touching", Fs, Vs))
    Vs2 = Vs.copy()
    Vs2[:, 2] = 0.2 * np.sin(2 * Vs[:, 1]) * (Vs[:, 0] - 0.3)
    out.append(("duplicate_seam_touching_bent", Fs, Vs2))
    # duplicated position: a separate small sheet whose corner sits exactly on
    # a vertex of the big sheet (touching at a single point) and one off-set
    A = grid(8, 8)
    Bf, Bv = grid(3, 3)
    Bv = rot_axis(rot_x(Bv, 60.0), (0.0, 1.0, 0.0), -30.0) + A[1][4 * 9 + 4]
    out.append(("duplicate_vertex_point_touch", *combine(A, (Bf, Bv))))
    Bv2 = Bv + np.array([0.0, 0.0, 2.0 ** -20])
    out.append(("near_vertex_point_gap", *combine(A, (Bf, Bv2))))
    return out


def ring_strip(nseg, nrad, theta_end, pitch, r0=1.0, r1=2.0):
    """An annulus strip from angle 0 to theta_end (nseg columns of nrad quads), at height
    z = pitch * theta / (2 pi): one flat layer, or a helix whose turns are `pitch` apart."""
    th = np.linspace(0.0, theta_end, nseg + 1)
    r = np.linspace(r0, r1, nrad + 1)
    T, R = np.meshgrid(th, r, indexing="ij")  # column i: angle th[i]
    V = np.column_stack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel(), (pitch * T / (2 * np.pi)).ravel()])
    F = []
    for i in range(nseg):
        for j in range(nrad):
            a = i * (nrad + 1) + j
            b, c = a + 1, a + nrad + 1
            F += [[a, c, c + 1], [a, c + 1, b]]
    return np.array(F, dtype=np.int64), V


def spiral_strip(nseg, turns, width, spacing):
    """A flat strip wound as an Archimedean spiral: the inner edge at radius 1 + spacing * theta /
    (2 pi), the outer `width` further out, so consecutive turns are spacing - width apart (0:
    touching along a curve). With nseg / turns a whole number, a turn's vertices sit at the
    angles of the turn before, so its chords run beside theirs, spacing - width apart."""
    th = np.linspace(0.0, 2 * np.pi * turns, nseg + 1)
    inner = 1.0 + spacing * th / (2 * np.pi)
    V = np.empty((2 * (nseg + 1), 3))
    V[0::2] = np.column_stack([inner * np.cos(th), inner * np.sin(th), np.zeros_like(th)])
    V[1::2] = np.column_stack([(inner + width) * np.cos(th), (inner + width) * np.sin(th), np.zeros_like(th)])
    F = []
    for i in range(nseg):
        a = 2 * i
        F += [[a, a + 2, a + 3], [a, a + 3, a + 1]]
    return np.array(F, dtype=np.int64), V


def _near_closing():
    """Contours that nearly meet themselves, the unprojected contour test's hardest input (and
    what a fuzzing session found to reach it most often): every normal agrees, so only the
    contour test can refuse to cull, and it must, exactly when the layers overlap."""
    out = []
    F, V = ring_strip(48, 2, 2 * np.pi, 0.0)
    W = V.copy()
    W[-3:] = W[:3]  # the last column exactly on the first (other vertex ids): touching along an edge
    out.append(("ring_closes_exactly", F, W))
    out.append(("ring_overlaps_by_1e-9", *ring_strip(48, 2, 2 * np.pi + 1e-9, 0.0)))
    out.append(("ring_short_by_1e-9", *ring_strip(48, 2, 2 * np.pi - 1e-9, 0.0)))
    F, V = ring_strip(56, 2, 2 * np.pi + 0.6, 1e-12)  # turns 1e-12 apart over 0.6 rad
    out.append(("helix_turns_1e-12_apart", F, V))
    W = V.copy()
    W[-5, 2] -= 1e-6  # a vertex of the upper turn pushed through the lower one
    out.append(("helix_turns_1e-12_apart_pierced", F, W))
    out.append(("helix_turns_1e-12_apart_offset_1e6", F, V + np.array([1e6, -1e6, 0.5])))
    out.append(("spiral_arms_touching", *spiral_strip(108, 2.25, 0.25, 0.25)))
    out.append(("spiral_arms_1e-10_apart", *spiral_strip(108, 2.25, 0.25, 0.25 + 1e-10)))
    out.append(("spiral_arms_overlap_1e-10", *spiral_strip(108, 2.25, 0.25, 0.25 - 1e-10)))
    return out


_CACHE = None


def all_cases():
    """List of (name, faces int64 (m,3), V float64 (n,3)); deterministic."""
    global _CACHE
    if _CACHE is None:
        cases = []
        for fam in (_folds, _crumples, _tubes, _holes_components, _fans,
                    _nonmanifold, _numerics, _near_closing):
            for name, F, V in fam():
                F = np.ascontiguousarray(F, dtype=np.int64).reshape(-1, 3)
                V = np.ascontiguousarray(V, dtype=np.float64).reshape(-1, 3)
                cases.append((name, F, V))
        names = [c[0] for c in cases]
        assert len(set(names)) == len(names), "duplicate case names"
        _CACHE = cases
    return [(n, F.copy(), V.copy()) for n, F, V in _CACHE]


def case_names():
    return [c[0] for c in all_cases()]


def case(name):
    for n, F, V in all_cases():
        if n == name:
            return n, F, V
    raise KeyError(name)


_ORACLE = {}


def oracle_pairs(name):
    """The brute-force oracle's colliding pairs of case `name`, as a frozenset (computed once)."""
    if name not in _ORACLE:
        from oracle import brute_force_pairs

        _, F, V = case(name)
        _ORACLE[name] = frozenset(brute_force_pairs(F, V))
    return _ORACLE[name]
