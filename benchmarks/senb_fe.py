"""The notched-beam K formula of rockcal checked by a linear-elastic finite-element model.

A 2D plane-stress beam (unit thickness, E = 1 Pa, nu = 0.25: K does not depend on E) of the
source study's geometry (length 220 mm, height W 50 mm, span S 160 mm, notch a 18 mm), with a
sharp edge crack at mid-span on the tension face, a point load P at the top centre and two point
supports at +-S/2 on the bottom. Half the beam is modelled: the uncracked ligament carries the
symmetry condition u_x = 0, the crack faces below it are free. The mesh is a graded tensor grid of
9-node quadrilaterals, with a band of square elements around the crack tip, refined by halving
every element.

K_I is computed by two independent routes that cross-check:
  compliance  G = (P^2 / 2) dC/da from the load-point compliance C(a) at five crack lengths
              (a/W 0.26 to 0.46 in steps of 0.05, all on the same mesh: only the symmetry condition moves), a cubic
              fitted to C(a) and differentiated at a/W = 0.36; K = sqrt(E G) (plane stress);
  J integral  the domain (equivalent-area) form of J around the tip at a/W = 0.36, K = sqrt(E J);
and, as a rougher third, by extrapolating K from the crack-opening displacement.
The dimensionless Y = K / (sigma_N sqrt(W)), sigma_N = 3 P S / (2 t W^2), is compared with
rockcal's senb_k(a/W, S/W) at S/W = 3.2 and with the ASTM E399 expression at S/W = 4 (a check of
the FE model itself).

Run by hand: `python benchmarks/senb_fe.py [--levels 3] [--json PATH]`. Uses one core.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # keep BLAS on one core: the machine is shared

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from skfem import (Basis, BilinearForm, ElementQuad1, ElementQuad2, ElementVector,  # noqa: E402
                   Functional, MeshQuad, condense, solve)
from skfem.helpers import ddot, eye, sym_grad, trace  # noqa: E402

from rockcal.labtests.kic import round_bar_kic, senb_k, senb_k_astm, senb_kic  # noqa: E402

E_PA = 1.0
NU = 0.25
LENGTH_M = 0.220
HEIGHT_M = 0.050
NOTCH_M = 0.018
SPANS_M = (0.160, 0.200)          # S/W = 3.2 (the source's beam) and 4 (ASTM E399)
LOAD_N_PER_M = 1.0                # P per metre of thickness, t = 1 m
CRACKS_OVER_W = np.round(np.arange(0.26, 0.4601, 0.05), 2)   # compliance samples
J_DOMAINS_OVER_W = ((0.05, 0.15), (0.10, 0.30))               # (r_in, r_out) of the J domain
COARSE_H_OVER_W = 0.05            # element size at the tip on the coarsest mesh
MAX_H_OVER_W = 0.15               # largest element size on the coarsest mesh
GRADING = 1.25                    # size ratio of neighbouring elements outside the tip band

LAB_PMAX_N = 1.453e3              # the lab's round bar: P_max, diameter, notch, span
LAB_DIAMETER_M = 0.050
LAB_NOTCH_M = 0.018
LAB_SPAN_M = 0.160
LAB_KIC = 1.057                   # MPa m^0.5, the source study's lab value
SOURCE_PFC2D_KIC = 1.163          # MPa m^0.5, the source study's PFC2D beam


def graded_interval(start_m: float, end_m: float, h_start_m: float, h_max_m: float) -> np.ndarray:
    """Node coordinates from start to end, first element h_start, each next one GRADING times
    larger up to h_max; the sizes are scaled to end exactly at `end_m`."""
    sizes = []
    h = h_start_m
    while sum(sizes) < abs(end_m - start_m):
        sizes.append(h)
        h = min(GRADING * h, h_max_m)
    sizes = np.array(sizes) * abs(end_m - start_m) / sum(sizes)
    return start_m + math.copysign(1, end_m - start_m) * np.concatenate([[0.0], np.cumsum(sizes)])


def coarse_grid() -> tuple[np.ndarray, np.ndarray]:
    """The coarsest x and y node lines of the half beam (x from the mid-span section, y from the
    bottom): square elements of COARSE_H_OVER_W W in the crack band, graded outside it, node lines
    at both support positions."""
    h = COARSE_H_OVER_W * HEIGHT_M
    h_max = MAX_H_OVER_W * HEIGHT_M
    band_low = CRACKS_OVER_W[0] * HEIGHT_M - 2 * h
    band_high = CRACKS_OVER_W[-1] * HEIGHT_M + 2 * h
    band_x = 0.30 * HEIGHT_M
    y = np.concatenate([graded_interval(band_low, 0.0, h, h_max)[::-1][:-1],
                        np.linspace(band_low, band_high, round((band_high - band_low) / h) + 1),
                        graded_interval(band_high, HEIGHT_M, h, h_max)[1:]])
    x_breaks = [band_x, *(s / 2 for s in SPANS_M), LENGTH_M / 2]
    x = [np.linspace(0.0, band_x, round(band_x / h) + 1)]
    for x0, x1 in zip(x_breaks[:-1], x_breaks[1:]):
        x.append(graded_interval(x0, x1, h * GRADING, h_max)[1:])
    return np.concatenate(x), y


def subdivide(nodes_m: np.ndarray, level: int) -> np.ndarray:
    """Split every interval of a 1D grid into 2**level equal parts."""
    parts = 2**level
    fine = [np.linspace(a, b, parts + 1)[:-1] for a, b in zip(nodes_m[:-1], nodes_m[1:])]
    return np.concatenate(fine + [nodes_m[-1:]])


def plane_stress(strain):
    """Plane-stress Hooke's law, sigma = E / (1 - nu^2) [(1 - nu) eps + nu tr(eps) I]."""
    return E_PA / (1 - NU**2) * ((1 - NU) * strain + NU * eye(trace(strain), 2))


@BilinearForm
def stiffness_form(u, v, w):
    return ddot(plane_stress(sym_grad(u)), sym_grad(v))


@Functional
def j_domain_form(w):
    """Integrand of the domain form of J for a crack growing in +y (the half beam's crack runs
    up the symmetry line): (sigma_ij du_i/dy - w_strain delta_2j) dq/dx_j."""
    grad_u = w["u"].grad
    strain = sym_grad(w["u"])
    stress = plane_stress(strain)
    energy_density = 0.5 * ddot(stress, strain)
    grad_q = w["q"].grad
    work = sum(stress[i, j] * grad_u[i, 1] * grad_q[j] for i in range(2) for j in range(2))
    return work - energy_density * grad_q[1]


def node_at(mesh: MeshQuad, x_m: float, y_m: float) -> int:
    """Index of the mesh vertex at (x, y)."""
    return int(np.argmin((mesh.p[0] - x_m) ** 2 + (mesh.p[1] - y_m) ** 2))


def solve_half_beam(basis: Basis, stiffness, crack_m: float, span_m: float) -> np.ndarray:
    """Displacements of the half beam with a crack of length `crack_m` under P/2 at the top of
    the symmetry line and a point support at x = S/2 on the bottom."""
    mesh = basis.mesh
    tol = 1e-9 * HEIGHT_M
    ligament = basis.get_dofs(lambda x: (x[0] < tol) & (x[1] > crack_m)).all("u^1")
    support = basis.nodal_dofs[1, node_at(mesh, span_m / 2, 0.0)]
    load = basis.nodal_dofs[1, node_at(mesh, 0.0, HEIGHT_M)]
    force = np.zeros(basis.N)
    force[load] = -LOAD_N_PER_M / 2
    fixed = np.concatenate([ligament, [support]])
    return solve(*condense(stiffness, force, D=fixed))


def load_point_compliance(basis: Basis, u: np.ndarray) -> float:
    """Load-point deflection of the full beam per unit load, C = delta / P (m per N/m)."""
    load = basis.nodal_dofs[1, node_at(basis.mesh, 0.0, HEIGHT_M)]
    return -u[load] / LOAD_N_PER_M


def k_from_compliance(crack_m: np.ndarray, compliance: np.ndarray, at_m: float) -> float:
    """K = sqrt(E G), G = (P^2 / 2t) dC/da, dC/da from a cubic fitted to C(a)."""
    scale = HEIGHT_M
    fit = np.polynomial.Polynomial.fit(crack_m / scale, compliance, 3)
    dC_da = fit.deriv()(at_m / scale) / scale
    return math.sqrt(E_PA * LOAD_N_PER_M**2 / 2 * dC_da)


def k_from_j(basis: Basis, u: np.ndarray, crack_m: float, r_in_m: float, r_out_m: float) -> float:
    """K = sqrt(E J) with J by the domain integral over the ring r_in..r_out around the tip
    (q = 1 inside r_in, falling linearly to 0 at r_out, interpolated bilinearly); the half beam's
    integral is doubled for the full crack."""
    mesh = basis.mesh
    r = np.hypot(mesh.p[0], mesh.p[1] - crack_m)
    q_nodes = np.clip((r_out_m - r) / (r_out_m - r_in_m), 0.0, 1.0)
    basis_q = basis.with_element(ElementQuad1())
    j_half = j_domain_form.assemble(basis, u=basis.interpolate(u), q=basis_q.interpolate(q_nodes))
    return math.sqrt(E_PA * 2 * j_half)


def k_from_opening(basis: Basis, u: np.ndarray, crack_m: float, h_m: float) -> float:
    """K extrapolated to the tip from the crack-face opening u_x(r) = (4 K / E) sqrt(r / 2 pi)
    (plane stress), by a straight line through K(r) for h < r <= 0.2 W."""
    tol = 1e-9 * HEIGHT_M
    dofs = basis.get_dofs(lambda x: (x[0] < tol) & (x[1] < crack_m)).all("u^1")
    r = crack_m - basis.doflocs[1, dofs]
    use = (r > h_m * 1.01) & (r <= 0.2 * HEIGHT_M)
    k_r = E_PA / 4 * np.sqrt(2 * math.pi / r[use]) * u[dofs][use]
    return float(np.polynomial.Polynomial.fit(r[use], k_r, 1)(0.0))


def nominal_stress(span_m: float) -> float:
    """sigma_N = 3 P S / (2 t W^2), t = 1 m."""
    return 3 * LOAD_N_PER_M * span_m / (2 * HEIGHT_M**2)


def run_level(level: int) -> dict:
    """Y by compliance, J (two domains) and crack opening at a/W = 0.36 for both spans on the
    mesh refined `level` times."""
    x, y = coarse_grid()
    mesh = MeshQuad.init_tensor(subdivide(x, level), subdivide(y, level))
    basis = Basis(mesh, ElementVector(ElementQuad2()))
    h_tip = COARSE_H_OVER_W * HEIGHT_M / 2**level
    t0 = time.perf_counter()
    stiffness = stiffness_form.assemble(basis)
    crack_m = CRACKS_OVER_W * HEIGHT_M
    result = {"level": level, "h_tip_over_W": h_tip / HEIGHT_M, "dofs": basis.N,
              "elements": mesh.nelements, "spans": {}}
    for span_m in SPANS_M:
        compliance = []
        for a in crack_m:
            u = solve_half_beam(basis, stiffness, a, span_m)
            compliance.append(load_point_compliance(basis, u))
            if math.isclose(a, NOTCH_M):
                u_notch = u
        scale = nominal_stress(span_m) * math.sqrt(HEIGHT_M)
        result["spans"][f"{span_m / HEIGHT_M:g}"] = {
            "Y_compliance": k_from_compliance(crack_m, np.array(compliance), NOTCH_M) / scale,
            "Y_J": [k_from_j(basis, u_notch, NOTCH_M, r_in * HEIGHT_M, r_out * HEIGHT_M) / scale
                    for r_in, r_out in J_DOMAINS_OVER_W],
            "Y_opening": k_from_opening(basis, u_notch, NOTCH_M, h_tip) / scale,
        }
    result["wall_s"] = time.perf_counter() - t0
    return result


def print_table(levels: list[dict], formulas: dict) -> None:
    """Y against mesh and formula, per span."""
    for span, formula in formulas.items():
        print(f"\nS/W = {span}, a/W = {NOTCH_M / HEIGHT_M:g}: Y = K / (sigma_N sqrt W); "
              f"formula {formula['name']} = {formula['Y']:.4f}")
        print(f"{'h_tip/W':>8} {'DOF':>7} {'compliance':>11} "
              + " ".join(f"{f'J {a:g}-{b:g}W':>11}" for a, b in J_DOMAINS_OVER_W)
              + f" {'opening':>9} {'J vs formula':>13}")
        for lev in levels:
            row = lev["spans"][span]
            print(f"{lev['h_tip_over_W']:>8.5f} {lev['dofs']:>7d} {row['Y_compliance']:>11.4f} "
                  + " ".join(f"{y:>11.4f}" for y in row["Y_J"])
                  + f" {row['Y_opening']:>9.4f} {100 * (row['Y_J'][-1] / formula['Y'] - 1):>+12.2f}%")


def thickness_comparison() -> dict:
    """K of the lab's round bar at P_max, and of a 2D beam loaded by P_max / D per unit
    thickness (the bar's load spread over its diameter as the beam's thickness)."""
    bar = round_bar_kic(LAB_PMAX_N, LAB_DIAMETER_M, LAB_NOTCH_M, LAB_SPAN_M) / 1e6
    beam = senb_kic(LAB_PMAX_N / LAB_DIAMETER_M, LAB_SPAN_M, HEIGHT_M, NOTCH_M) / 1e6
    return {"round_bar_kic_MPa_sqrt_m": bar, "beam_kic_at_Pmax_over_D_MPa_sqrt_m": beam,
            "beam_over_bar": beam / bar, "lab_reported_kic": LAB_KIC,
            "source_pfc2d_kic": SOURCE_PFC2D_KIC}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, default=3, help="number of meshes (each halves h)")
    parser.add_argument("--json", help="also write the numbers to this file")
    args = parser.parse_args()

    t0 = time.perf_counter()
    a_over_W = NOTCH_M / HEIGHT_M
    formulas = {"3.2": {"name": "rockcal senb_k(0.36, 3.2)", "Y": senb_k(a_over_W, 3.2)},
                "4": {"name": "ASTM E399 senb_k_astm(0.36)", "Y": senb_k_astm(a_over_W)}}
    levels = []
    for level in range(args.levels):
        levels.append(run_level(level))
        print(f"mesh {level}: h_tip/W {levels[-1]['h_tip_over_W']:g}, {levels[-1]['dofs']} DOF, "
              f"{levels[-1]['wall_s']:.1f} s", flush=True)
    print_table(levels, formulas)

    thickness = thickness_comparison()
    print(f"\nLab round bar (D {1e3 * LAB_DIAMETER_M:g}, a {1e3 * LAB_NOTCH_M:g}, "
          f"S {1e3 * LAB_SPAN_M:g} mm) at P_max {LAB_PMAX_N / 1e3:g} kN, Ouchterlony: "
          f"K_IC {thickness['round_bar_kic_MPa_sqrt_m']:.3f} MPa m^0.5 (reported {LAB_KIC})")
    print(f"2D beam (W {1e3 * HEIGHT_M:g}, a {1e3 * NOTCH_M:g}, S {1e3 * LAB_SPAN_M:g} mm) at "
          f"P_max / D = {LAB_PMAX_N / LAB_DIAMETER_M / 1e3:g} kN/m: "
          f"K {thickness['beam_kic_at_Pmax_over_D_MPa_sqrt_m']:.3f} MPa m^0.5 "
          f"({100 * (thickness['beam_over_bar'] - 1):+.1f} % against the round bar; "
          f"source PFC2D beam {SOURCE_PFC2D_KIC})")
    wall = time.perf_counter() - t0
    print(f"\nwall time {wall:.1f} s")

    if args.json:
        with open(args.json, "w") as f:
            json.dump({"a_over_W": a_over_W, "E_Pa": E_PA, "nu": NU, "formulas": formulas,
                       "levels": levels, "thickness": thickness, "wall_s": wall}, f, indent=2)


if __name__ == "__main__":
    main()
