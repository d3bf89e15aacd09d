# Copied unchanged (but for these two lines) from the project's shared benchmark folder, bench/bond_loop.py,
# so that engine_profile.py runs from this repository alone.
"""The speed limit of a 2D bonded-disk step on one core: a bare numba loop over bonds (force + moment,
Hooke springs) and a velocity-Verlet update, nothing else (no contacts, damping, breakage or neighbour
search). Prints ms per step and particle-steps/s for N disks on a jittered triangular lattice.
Usage: python bond_loop.py [N] [steps]"""
import sys, time
import numpy as np
import numba
from numba import njit


@njit
def step(pos, vel, rot, spin, force, moment, bi, bj, kn, ks, kb, fn0, inv_m, inv_i, rad, dt, nsteps):
    n = pos.shape[0]
    for _ in range(nsteps):
        for k in range(n):
            force[k, 0] = 0.0; force[k, 1] = 0.0; moment[k] = 0.0
        for b in range(bi.shape[0]):
            i = bi[b]; j = bj[b]
            dx = pos[j, 0] - pos[i, 0]; dy = pos[j, 1] - pos[i, 1]
            d = np.sqrt(dx * dx + dy * dy)
            nx = dx / d; ny = dy / d
            fn = kn * (d - fn0[b])
            vs = (vel[j, 1] - vel[i, 1]) * nx - (vel[j, 0] - vel[i, 0]) * ny - spin[i] * rad[i] - spin[j] * rad[j]
            fs = ks * vs * dt
            m = kb * (rot[j] - rot[i])
            fx = fn * nx - fs * ny; fy = fn * ny + fs * nx
            force[i, 0] += fx; force[i, 1] += fy; force[j, 0] -= fx; force[j, 1] -= fy
            moment[i] += m + rad[i] * fs; moment[j] += -m + rad[j] * fs
        for k in range(n):
            vel[k, 0] += force[k, 0] * inv_m[k] * dt; vel[k, 1] += force[k, 1] * inv_m[k] * dt
            spin[k] += moment[k] * inv_i[k] * dt
            pos[k, 0] += vel[k, 0] * dt; pos[k, 1] += vel[k, 1] * dt; rot[k] += spin[k] * dt


def main():
    n_target = int(sys.argv[1]) if len(sys.argv) > 1 else 12000
    steps = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
    rng = np.random.default_rng(0)
    r = 2.5e-4
    cols = int(np.sqrt(n_target / 2)); rows = n_target // cols
    pos = np.array([[(2 * c + (w % 2)) * r, w * np.sqrt(3) * r] for w in range(rows) for c in range(cols)])
    order = np.lexsort((pos[:, 0], np.floor(pos[:, 1] / (4 * r))))
    pos = pos[order] + rng.normal(0, 1e-3 * r, pos.shape)
    n = len(pos)
    from scipy.spatial import cKDTree
    pairs = cKDTree(pos).query_pairs(2.05 * r, output_type="ndarray")
    # thin to about 2 bonds per disk (a random packing's bonded coordination ~4)
    pairs = pairs[rng.random(len(pairs)) < 4.1 / 6.0]
    bi, bj = pairs[:, 0].copy(), pairs[:, 1].copy()
    d0 = np.linalg.norm(pos[bj] - pos[bi], axis=1)
    rad = np.full(n, r); m = 2622 * np.pi * r * r; inv_m = np.full(n, 1 / m); inv_i = np.full(n, 2 / (m * r * r))
    kn = 2e10; dt = 0.2 * np.sqrt(m / kn)
    vel = rng.normal(0, 1e-3, (n, 2)); spin = np.zeros(n); rot = np.zeros(n)
    force = np.zeros((n, 2)); moment = np.zeros(n)
    args = (pos, vel, rot, spin, force, moment, bi, bj, kn, kn / 2, kn * r * r / 3, d0, inv_m, inv_i, rad, dt)
    step(*args, 10)
    t = time.perf_counter(); step(*args, steps); w = time.perf_counter() - t
    print(f"bare bond loop, one core: {n} disks, {len(bi)} bonds: {1e3 * w / steps:.3f} ms/step, "
          f"{n * steps / w / 1e6:.1f} M particle-steps/s, {len(bi) * steps / w / 1e6:.1f} M bond-steps/s")


if __name__ == "__main__":
    main()
