"""The notched-beam K formula of rockcal checked by a linear-elastic finite-element model.

A 2D plane-stress beam (unit thickness, E = 1 Pa, nu = 0.25; K does not depend on E, and with
loads given as forces not on nu either) of the source study's geometry (length 220 mm, height
W 50 mm, notch a 18 mm), with a sharp edge crack at mid-span on the tension face. Three load
cases:
  S/W = 3.2   point load P at the top centre, point supports at +-S/2 = 80 mm (the source's beam);
  S/W = 4     the same with supports at +-100 mm: the ASTM E399 beam, a check of the model;
  pure bend.  a linear end traction of moment M (S/W -> infinity): Tada's solution, a second check.
Half the beam is modelled: the uncracked ligament carries the symmetry condition u_x = 0, the crack
faces below it are free. Quadratic (6-node) triangles on a graded grid, refined around the crack
tips: every mesh level halves the elements at the tips.

K_I is computed by two independent routes that cross-check:
  compliance  G = (Q^2 / 2) dC/da with C = 2 f.u / Q^2 (f.u the work of the half beam's loads,
              Q = P or M) at five crack lengths a/W = 0.26 ... 0.46 (the same mesh for all: only
              the symmetry condition moves), a cubic fitted to C(a), differentiated at a/W = 0.36;
  J integral  the domain (equivalent-area) form of J around the tip at a/W = 0.36, on two rings;
both K = sqrt(E G) (plane stress). Y = K / (sigma_N sqrt(W)), sigma_N = 3 P S / (2 t W^2) (three-
point bending) or 6 M / (t W^2) (pure bending), is compared with rockcal's senb_k(0.36, 3.2),
with ASTM E399's senb_k_astm(0.36) and with Tada's senb_k_pure_bending(0.36). The errors fall
as h_tip (the tip singularity), so a Richardson extrapolation (order 1) of the two finest meshes
is printed as the converged value.

Also printed: K of the lab's round bar at its P_max (Ouchterlony) and K of a 2D beam loaded by
P_max / D per unit thickness (the bar's load spread over its diameter as thickness).

Run by hand: `python benchmarks/senb_fe.py [--levels 7] [--json PATH]`. Uses one core, ~10 s.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # keep BLAS on one core: the machine is shared

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from skfem import (Basis, BilinearForm, ElementTriP1, ElementTriP2, ElementVector,  # noqa: E402
                   FacetBasis, Functional, LinearForm, MeshTri, condense, solve)
from skfem.helpers import ddot, eye, sym_grad, trace  # noqa: E402

from rockcal.labtests.kic import (round_bar_kic, senb_k, senb_k_astm,  # noqa: E402
                                  senb_k_pure_bending, senb_kic)

E_PA = 1.0
NU = 0.25
LENGTH_M = 0.220
HEIGHT_M = 0.050
NOTCH_M = 0.018
LOAD = 1.0                        # P in N per metre of thickness, or M in N m per metre (t = 1 m)
SPANS_OVER_W = (3.2, 4.0, math.inf)                           # inf: pure bending
CRACKS_OVER_W = np.array([0.26, 0.31, 0.36, 0.41, 0.46])      # compliance samples
J_RINGS_OVER_W = ((0.05, 0.15), (0.10, 0.30))                 # (r_in, r_out) of the J domains
COARSE_H_OVER_W = 0.05            # element size in the crack band of the coarsest mesh
MAX_H_OVER_W = 0.15               # largest element size
GRADING = 1.25                    # size ratio of neighbouring elements outside the band
REFINE_RADIUS_IN_H = 8            # each level refines elements this many tip sizes from a tip

LAB_PMAX_N = 1.453e3              # the lab's round bar: P_max, diameter, notch, span
LAB_DIAMETER_M = 0.050
LAB_NOTCH_M = 0.018
LAB_SPAN_M = 0.160
LAB_KIC = 1.057                   # MPa m^0.5, the source study's lab value
SOURCE_PFC2D_KIC = 1.163          # MPa m^0.5, the source study's PFC2D beam


# --- mesh --------------------------------------------------------------------------------------

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
    """x and y node lines of the half beam (x from the mid-span section, y up from the cracked
    face): squares of COARSE_H_OVER_W W around the crack tips, graded outside, node lines at
    the supports of both spans."""
    h = COARSE_H_OVER_W * HEIGHT_M
    h_max = MAX_H_OVER_W * HEIGHT_M
    band_low = CRACKS_OVER_W[0] * HEIGHT_M - 2 * h
    band_high = CRACKS_OVER_W[-1] * HEIGHT_M + 2 * h
    band_x = 0.30 * HEIGHT_M
    y = np.concatenate([graded_interval(band_low, 0.0, h, h_max)[::-1][:-1],
                        np.linspace(band_low, band_high, round((band_high - band_low) / h) + 1),
                        graded_interval(band_high, HEIGHT_M, h, h_max)[1:]])
    supports = [s * HEIGHT_M / 2 for s in SPANS_OVER_W if math.isfinite(s)]
    x_breaks = [band_x, *supports, LENGTH_M / 2]
    x = [np.linspace(0.0, band_x, round(band_x / h) + 1)]
    for x0, x1 in zip(x_breaks[:-1], x_breaks[1:]):
        x.append(graded_interval(x0, x1, h * GRADING, h_max)[1:])
    return np.concatenate(x), np.clip(y, 0.0, HEIGHT_M)


def beam_mesh(level: int) -> MeshTri:
    """The half beam's triangle mesh, refined `level` times around every crack-tip position,
    each time halving the elements within REFINE_RADIUS_IN_H of their new size from a tip."""
    mesh = MeshTri.init_tensor(*coarse_grid())
    tips_y = CRACKS_OVER_W * HEIGHT_M
    for step in range(1, level + 1):
        radius = REFINE_RADIUS_IN_H * COARSE_H_OVER_W * HEIGHT_M / 2**step
        x, y = mesh.p[0, mesh.t], mesh.p[1, mesh.t]                # (3, elements)
        distance = np.min([np.hypot(x, y - tip).min(axis=0) for tip in tips_y], axis=0)
        mesh = mesh.refined(np.nonzero(distance < radius)[0])
    return mesh


def tip_element_size(mesh: MeshTri, tip_y_m: float) -> float:
    """Longest edge of the elements touching the tip."""
    tip = int(np.argmin(np.hypot(mesh.p[0], mesh.p[1] - tip_y_m)))
    elements = mesh.t[:, np.any(mesh.t == tip, axis=0)]
    corners = mesh.p[:, elements]                                   # (2, 3, elements)
    edges = corners - np.roll(corners, 1, axis=1)
    return float(np.hypot(edges[0], edges[1]).max())


def node_at(mesh: MeshTri, x_m: float, y_m: float) -> int:
    """Index of the mesh vertex at (x, y)."""
    return int(np.argmin(np.hypot(mesh.p[0] - x_m, mesh.p[1] - y_m)))


# --- elasticity --------------------------------------------------------------------------------

def plane_stress(strain):
    """Plane-stress Hooke's law, sigma = E / (1 - nu^2) [(1 - nu) eps + nu tr(eps) I]."""
    return E_PA / (1 - NU**2) * ((1 - NU) * strain + NU * eye(trace(strain), 2))


@BilinearForm
def stiffness_form(u, v, w):
    return ddot(plane_stress(sym_grad(u)), sym_grad(v))


@LinearForm
def bending_traction_form(v, w):
    """Normal traction sigma_b (1 - 2y/W), sigma_b = 6 M / W^2, on the beam's end: a moment M
    per unit thickness, tension on the cracked face."""
    return 6 * LOAD / HEIGHT_M**2 * (1 - 2 * w.x[1] / HEIGHT_M) * v[0]


@Functional
def j_domain_form(w):
    """Integrand of the domain form of J for a crack growing in +y (the half beam's crack runs
    up the symmetry line): (sigma_ij du_i/dy - w_strain delta_2j) dq/dx_j."""
    grad_u = w["u"].grad
    strain = sym_grad(w["u"])
    stress = plane_stress(strain)
    grad_q = w["q"].grad
    work = sum(stress[i, j] * grad_u[i, 1] * grad_q[j] for i in range(2) for j in range(2))
    return work - 0.5 * ddot(stress, strain) * grad_q[1]


def load_case(basis: Basis, span_over_W: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Load vector of the half beam, the constrained DOF other than symmetry, and sigma_N:
    three-point bending (P/2 at the top of the symmetry line, a support at S/2) or, for an
    infinite span, pure bending (end traction, one vertical DOF held)."""
    mesh = basis.mesh
    force = np.zeros(basis.N)
    top = basis.nodal_dofs[1, node_at(mesh, 0.0, HEIGHT_M)]
    if math.isfinite(span_over_W):
        force[top] = -LOAD / 2
        held = basis.nodal_dofs[1, node_at(mesh, span_over_W * HEIGHT_M / 2, 0.0)]
        return force, np.array([held]), 3 * LOAD * span_over_W / (2 * HEIGHT_M)
    end = mesh.facets_satisfying(lambda x: x[0] > LENGTH_M / 2 - 1e-9 * HEIGHT_M)
    force += bending_traction_form.assemble(FacetBasis(mesh, basis.elem, facets=end))
    return force, np.array([top]), 6 * LOAD / HEIGHT_M**2


def solve_half_beam(basis: Basis, stiffness, force: np.ndarray, held: np.ndarray,
                    crack_m: float) -> np.ndarray:
    """Displacements with a crack of length `crack_m`: u_x = 0 on the ligament above it."""
    ligament = basis.get_dofs(lambda x: (x[0] < 1e-9 * HEIGHT_M) & (x[1] > crack_m)).all("u^1")
    return solve(*condense(stiffness, force, D=np.concatenate([ligament, held])))


# --- K -----------------------------------------------------------------------------------------

def k_from_compliance(crack_m: np.ndarray, compliance: np.ndarray, at_m: float) -> float:
    """K = sqrt(E G), G = (Q^2 / 2t) dC/da, dC/da from a cubic fitted to C(a)."""
    fit = np.polynomial.Polynomial.fit(crack_m / HEIGHT_M, compliance, 3)
    dC_da = fit.deriv()(at_m / HEIGHT_M) / HEIGHT_M
    return math.sqrt(E_PA * LOAD**2 / 2 * dC_da)


def k_from_j(basis: Basis, u: np.ndarray, crack_m: float, r_in_m: float, r_out_m: float) -> float:
    """K = sqrt(E J), J by the domain integral over the ring r_in..r_out around the tip (q = 1
    inside r_in, falling linearly to 0 at r_out, interpolated linearly); the half beam's
    integral is doubled for the full crack."""
    r = np.hypot(basis.mesh.p[0], basis.mesh.p[1] - crack_m)
    q_nodes = np.clip((r_out_m - r) / (r_out_m - r_in_m), 0.0, 1.0)
    basis_q = basis.with_element(ElementTriP1())
    j_half = j_domain_form.assemble(basis, u=basis.interpolate(u), q=basis_q.interpolate(q_nodes))
    return math.sqrt(E_PA * 2 * j_half)


def run_level(level: int) -> dict:
    """Y by compliance and by J (two rings) at a/W = 0.36 for every load case on one mesh."""
    t0 = time.perf_counter()
    mesh = beam_mesh(level)
    basis = Basis(mesh, ElementVector(ElementTriP2()))
    stiffness = stiffness_form.assemble(basis)
    crack_m = CRACKS_OVER_W * HEIGHT_M
    result = {"level": level, "h_tip_over_W": tip_element_size(mesh, NOTCH_M) / HEIGHT_M,
              "dofs": int(basis.N), "elements": int(mesh.nelements), "cases": {}}
    for span_over_W in SPANS_OVER_W:
        force, held, sigma_N = load_case(basis, span_over_W)
        compliance = []
        for a in crack_m:
            u = solve_half_beam(basis, stiffness, force, held, a)
            compliance.append(2 * force @ u / LOAD**2)
            if math.isclose(a, NOTCH_M):
                u_notch = u
        scale = sigma_N * math.sqrt(HEIGHT_M)
        result["cases"][f"{span_over_W:g}"] = {
            "Y_compliance": k_from_compliance(crack_m, np.array(compliance), NOTCH_M) / scale,
            "Y_J": [k_from_j(basis, u_notch, NOTCH_M, r_in * HEIGHT_M, r_out * HEIGHT_M) / scale
                    for r_in, r_out in J_RINGS_OVER_W]}
    result["wall_s"] = time.perf_counter() - t0
    return result


def richardson(coarse: float, fine: float) -> float:
    """Order-1 extrapolation of two values on meshes a factor 2 apart."""
    return 2 * fine - coarse


def formulas() -> dict:
    """rockcal's Y at a/W = 0.36 for each load case."""
    x = NOTCH_M / HEIGHT_M
    return {"3.2": {"name": "rockcal senb_k(0.36, 3.2)", "Y": senb_k(x, 3.2)},
            "4": {"name": "ASTM E399 senb_k_astm(0.36)", "Y": senb_k_astm(x)},
            "inf": {"name": "Tada senb_k_pure_bending(0.36)", "Y": senb_k_pure_bending(x)}}


def converged(levels: list[dict]) -> dict:
    """Per load case: the J value (outer ring) and compliance value extrapolated from the two
    finest meshes, and the observed convergence order of J from the three finest."""
    out = {}
    for case in levels[-1]["cases"]:
        j = [lev["cases"][case]["Y_J"][-1] for lev in levels]
        c = [lev["cases"][case]["Y_compliance"] for lev in levels]
        order = math.log2((j[-2] - j[-3]) / (j[-1] - j[-2])) if len(j) >= 3 else float("nan")
        out[case] = {"Y_J": richardson(j[-2], j[-1]), "Y_compliance": richardson(c[-2], c[-1]),
                     "observed_order": order}
    return out


def print_table(levels: list[dict], limit: dict, reference: dict) -> None:
    """Y against mesh and formula, per load case."""
    for case, formula in reference.items():
        title = "pure bending" if case == "inf" else f"S/W = {case}"
        print(f"\n{title}, a/W = {NOTCH_M / HEIGHT_M:g}: Y = K / (sigma_N sqrt W); "
              f"{formula['name']} = {formula['Y']:.4f}")
        rings = " ".join(f"{f'J {a:g}-{b:g}W':>11}" for a, b in J_RINGS_OVER_W)
        print(f"{'level':>5} {'h_tip/W':>8} {'DOF':>6} {'compliance':>11} {rings} {'vs formula':>11}")
        for lev in levels:
            row = lev["cases"][case]
            print(f"{lev['level']:>5} {lev['h_tip_over_W']:>8.5f} {lev['dofs']:>6d} "
                  f"{row['Y_compliance']:>11.4f} " + " ".join(f"{y:>11.4f}" for y in row["Y_J"])
                  + f" {100 * (row['Y_J'][-1] / formula['Y'] - 1):>+10.2f}%")
        lim = limit[case]
        print(f"{'h->0':>5} {'':>8} {'':>6} {lim['Y_compliance']:>11.4f} {'':>11} "
              f"{lim['Y_J']:>11.4f} {100 * (lim['Y_J'] / formula['Y'] - 1):>+10.2f}%  "
              f"(Richardson; observed order {lim['observed_order']:.2f})")


def thickness_comparison() -> dict:
    """K of the lab's round bar at P_max, and of a 2D beam loaded by P_max / D per unit
    thickness (the bar's load spread over its diameter as the beam's thickness)."""
    bar = round_bar_kic(LAB_PMAX_N, LAB_DIAMETER_M, LAB_NOTCH_M, LAB_SPAN_M) / 1e6
    beam = senb_kic(LAB_PMAX_N / LAB_DIAMETER_M, LAB_SPAN_M, HEIGHT_M, NOTCH_M) / 1e6
    return {"round_bar_kic_MPa_sqrt_m": bar, "beam_kic_at_Pmax_over_D_MPa_sqrt_m": beam,
            "beam_over_bar": beam / bar, "bar_pmax_per_m_for_equal_beam_kic_kN": (
                LAB_PMAX_N / LAB_DIAMETER_M * bar / beam / 1e3),
            "lab_reported_kic": LAB_KIC, "source_pfc2d_kic": SOURCE_PFC2D_KIC}


def print_thickness(t: dict) -> None:
    print(f"\nLab round bar (D {1e3 * LAB_DIAMETER_M:g}, a {1e3 * LAB_NOTCH_M:g}, "
          f"S {1e3 * LAB_SPAN_M:g} mm) at P_max {LAB_PMAX_N / 1e3:g} kN, Ouchterlony: "
          f"K_IC {t['round_bar_kic_MPa_sqrt_m']:.3f} MPa m^0.5 (reported {LAB_KIC})")
    print(f"2D beam (W {1e3 * HEIGHT_M:g}, a {1e3 * NOTCH_M:g}, S {1e3 * LAB_SPAN_M:g} mm) at "
          f"P_max / D = {LAB_PMAX_N / LAB_DIAMETER_M / 1e3:g} kN/m: "
          f"K {t['beam_kic_at_Pmax_over_D_MPa_sqrt_m']:.3f} MPa m^0.5 "
          f"({100 * (t['beam_over_bar'] - 1):+.1f} % against the round bar); the beam matches the "
          f"bar's K at {t['bar_pmax_per_m_for_equal_beam_kic_kN']:.1f} kN/m = P_max / "
          f"{LAB_PMAX_N / 1e3 / t['bar_pmax_per_m_for_equal_beam_kic_kN'] * 1e3:.1f} mm "
          f"(source PFC2D beam K_IC {SOURCE_PFC2D_KIC})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, default=7, help="number of meshes (each halves h_tip)")
    parser.add_argument("--json", help="also write the numbers to this file")
    args = parser.parse_args()

    t0 = time.perf_counter()
    levels = []
    for level in range(args.levels):
        levels.append(run_level(level))
        print(f"mesh {level}: h_tip/W {levels[-1]['h_tip_over_W']:.5f}, {levels[-1]['dofs']} DOF, "
              f"{levels[-1]['wall_s']:.1f} s", flush=True)
    reference = formulas()
    limit = converged(levels)
    print_table(levels, limit, reference)
    fe_interpolated = limit["inf"]["Y_J"] + 4 / 3.2 * (limit["4"]["Y_J"] - limit["inf"]["Y_J"])
    print(f"\nrockcal's interpolation in W/S applied to the FE end values (S/W 4 and pure bending) "
          f"gives Y(3.2) = {fe_interpolated:.4f} against the FE's {limit['3.2']['Y_J']:.4f} "
          f"({100 * (fe_interpolated / limit['3.2']['Y_J'] - 1):+.2f} %)")

    thickness = thickness_comparison()
    print_thickness(thickness)
    wall = time.perf_counter() - t0
    print(f"\nwall time {wall:.1f} s")

    if args.json:
        with open(args.json, "w") as f:
            json.dump({"a_over_W": NOTCH_M / HEIGHT_M, "E_Pa": E_PA, "nu": NU,
                       "formulas": reference, "levels": levels, "converged": limit,
                       "fe_interpolated_Y_3.2": fe_interpolated, "thickness": thickness,
                       "wall_s": wall}, f, indent=2)


if __name__ == "__main__":
    main()
