"""Figures a rock engineer expects; matplotlib without a display."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402
from matplotlib.patches import Wedge  # noqa: E402

from rockcal.labtests.damage import VOLUMETRIC_NAME, crack_strain, crack_stresses, volumetric_strain  # noqa: E402
from rockcal.labtests.envelope import check_peaks, fit_hoek_brown, fit_mohr_coulomb  # noqa: E402
from rockcal.output_files import save_figure  # noqa: E402
from rockcal.errors import InputError  # noqa: E402


def crack_pattern(positions, radius, cracks: dict, path: Path, title: str, rig=(),
                  axes: tuple[str, str] = ("x", "y")) -> None:
    """The specimen's disks in grey with broken bonds: tension red, shear blue; `rig`: circles
    (x, y, radius; m) of the loading rig (a beam's pin and supports), drawn dark; `axes`: the
    coordinates drawn (a 3D specimen's front view: x and z). 3D positions, (n, 3), are drawn
    from the front (x, z); `crack_planes` draws them on three planes."""
    if np.shape(positions)[1] == 3:
        positions, cracks, axes = plane_view(positions, "xz"), {
            mode: plane_view(xyz, "xz") for mode, xyz in cracks.items()}, ("x", "z")
    width_m = positions[:, 0].max() - positions[:, 0].min()
    height_m = positions[:, 1].max() - positions[:, 1].min()
    fig, ax = plt.subplots(figsize=_specimen_figsize(width_m, height_m))
    mm = positions * 1e3
    disks = EllipseCollection(2e3 * radius, 2e3 * radius, 0, units="xy", offsets=mm,
                              offset_transform=ax.transData, facecolors="0.85", edgecolors="0.6",
                              linewidths=0.2)
    ax.add_collection(disks)
    for x, y, r in rig:
        ax.add_patch(plt.Circle((1e3 * x, 1e3 * y), 1e3 * r, facecolor="0.35", edgecolor="0.1"))
    for mode, colour in CRACK_COLOURS:
        xy = cracks[mode] * 1e3
        ax.plot(xy[:, 0], xy[:, 1], "o", ms=2, color=colour, label=f"{mode} ({len(xy)})")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel(f"{axes[0]} (mm)")
    ax.set_ylabel(f"{axes[1]} (mm)")
    ax.set_title(title)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    _save(fig, path)


CRACK_COLOURS = (("tension", "tab:red"), ("shear", "tab:blue"))
AXIS = {"x": 0, "y": 1, "z": 2}
# A 3D specimen's views as in a third-angle drawing: the top above the front, the side to its
# right; each (name, plane: the coordinate across, the one up, its place in a 2 x 2 grid)
VIEWS = (("front", "xz", (1, 0)), ("side", "yz", (1, 1)), ("top", "xy", (0, 0)))
ROUND_IN = {"cylinder": "xy", "disk": "xz"}  # the plane each round shape is a circle in
# Seen through the specimen's depth the cracks crowd: the many tension cracks small and
# see-through, so that where they gather shows, the few shear cracks opaque over them
PLANE_MARKERS = {"tension": dict(ms=1.5, alpha=0.5), "shear": dict(ms=2)}


def plane_view(xyz, plane: str) -> np.ndarray:
    """3D positions (n, 3) projected on `plane` ("xz", "yz" or "xy"): (n, 2), the first
    coordinate named across, the second up."""
    return np.asarray(xyz, float)[:, [AXIS[plane[0]], AXIS[plane[1]]]]


def outline(shape: str, size_m, plane: str):
    """A 3D specimen's outline on `plane` in mm (`specimens3d.specimen.Specimen3D`: its `shape` fills
    the box [0, size] in x, y and z): a circle (a half disk's half) where the shape is round,
    else a rectangle."""
    across, up = (1e3 * size_m[AXIS[c]] for c in plane)
    style = dict(fill=False, edgecolor="0.3", linewidth=1.0)
    if shape == "half_disk" and plane == "xz":  # standing on its flat side
        return Wedge((across / 2, 0), across / 2, 0, 180, **style)
    if ROUND_IN.get(shape) == plane:
        return plt.Circle((across / 2, up / 2), across / 2, **style)
    return plt.Rectangle((0, 0), across, up, **style)


def specimen_cracks(specimen, positions, cracks: dict, path: Path, title: str, rig=(),
                    undeformed: bool = False) -> None:
    """A specimen's broken bonds as its dimension shows them (the one place a figure asks it):
    over a 2D specimen's disks at `positions` (`crack_pattern`, with the `rig`'s circles; the
    title says when they are the `undeformed` specimen's), or a 3D specimen's projected on
    three planes (`crack_planes`); cracks stored before 3D runs kept their y, (x, z) rows, over
    the 3D specimen's spheres from the front."""
    if specimen.dimensions == 2:
        crack_pattern(positions, specimen.radius, cracks, path, title + (" (undeformed specimen)" if undeformed else ""),
                      rig)
    elif cracks["tension"].shape[1] == 3:
        crack_planes(cracks, specimen.shape, specimen.size_m, path, f"{title} seen from the front, the side and the top")
    else:
        crack_pattern(plane_view(positions, "xz"), specimen.radius, cracks, path,
                      f"{title} (undeformed specimen, seen from the front)", axes=("x", "z"))


def crack_planes(cracks: dict, shape: str, size_m, path: Path, title: str) -> None:
    """A 3D specimen's broken bonds, (n, 3) m by mode, projected on the front (x-z), side (y-z)
    and top (x-y) planes, tension red, shear blue, within the specimen's outline on each
    (`crack_planes_figure`)."""
    _save(crack_planes_figure(cracks, shape, size_m, title), path)


def crack_planes_figure(cracks: dict, shape: str, size_m, title: str):
    """`crack_planes`' figure: three panels at one scale in mm, the top above the front and the
    side to its right, the legend in the fourth corner. The spheres are not drawn: seen through
    the specimen they fill its outline evenly and hide the cracks."""
    sx, sy, sz = (1e3 * s for s in size_m)
    margin = 0.06 * max(sx, sy, sz)
    across, up = sx + sy + 4 * margin, sy + sz + 4 * margin
    inch_per_mm = min(7.0 / across, 7.5 / up)
    fig = plt.figure(figsize=(inch_per_mm * across + 1.6, inch_per_mm * up + 1.6))
    grid = fig.add_gridspec(2, 2, width_ratios=(sx + 2 * margin, sy + 2 * margin),
                            height_ratios=(sy + 2 * margin, sz + 2 * margin))
    for name, plane, (row, column) in VIEWS:
        ax = fig.add_subplot(grid[row, column])
        _crack_view(ax, cracks, shape, size_m, plane, margin)
        ax.set_title(f"{name} ({plane[0]}–{plane[1]})", fontsize=9)
    legend = fig.add_subplot(grid[0, 1])
    legend.axis("off")
    legend.legend(*fig.axes[0].get_legend_handles_labels(), loc="center", fontsize=8, frameon=False,
                  markerscale=3)
    fig.suptitle(title)
    return fig


def _crack_view(ax, cracks: dict, shape: str, size_m, plane: str, margin_mm: float) -> None:
    """One panel of `crack_planes_figure`: the cracks on `plane`, the outline, axes in mm."""
    ax.add_patch(outline(shape, size_m, plane))
    for mode, colour in CRACK_COLOURS:
        xy = plane_view(cracks[mode], plane) * 1e3
        ax.plot(xy[:, 0], xy[:, 1], "o", color=colour, label=f"{mode} ({len(xy)})", **PLANE_MARKERS[mode])
    across, up = (1e3 * size_m[AXIS[c]] for c in plane)
    ax.set_xlim(-margin_mm, across + margin_mm)
    ax.set_ylim(-margin_mm, up + margin_mm)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{plane[0]} (mm)")
    ax.set_ylabel(f"{plane[1]} (mm)")


def _specimen_figsize(width_m: float, height_m: float) -> tuple[float, float]:
    """Figure size (inches) of a specimen drawing: 8 high when tall, 10 wide when wide."""
    if height_m >= width_m:
        return 4 + 4 * width_m / height_m, 8
    return 10, 2 + 8 * height_m / width_m


def stress_strain(curve, path: Path, title: str, rig, stress: str = "axial stress (MPa)") -> None:
    """Axial stress against axial and lateral strain (%), with CI and CD marked when the curve
    counts its broken bonds (a compression curve's fourth column), read over the `rig`'s
    lateral strains (`rockcal.labtests.rig.Rig`)."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(100 * curve[:, 0], curve[:, 2], label="axial")
    ax.plot(-100 * curve[:, 1], curve[:, 2], label="lateral")
    mark_crack_stresses(ax, curve, rig.lateral_strains)
    _finish(fig, ax, "strain (%)  (lateral shown negative)", stress, title, path)


def tension_curve(curve, path: Path, title: str, rig=None) -> None:
    """Tensile stress against axial strain (%) of a direct tension test, its peak marked (a
    test's curve figure takes its `rig`; this one does not read it)."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(100 * curve[:, 0], curve[:, 1])
    _mark_peak(ax, 100 * curve[:, 0], curve[:, 1], "direct tensile strength {:.2f} MPa")
    _finish(fig, ax, "axial strain (%)", "tensile stress (MPa)", title, path)


def deviatoric_stress_strain(curve, path: Path, title: str, rig) -> None:
    """A confined compression curve: q = sigma1 - sigma3 against axial and lateral strain."""
    stress_strain(curve, path, title, rig, "deviatoric stress q = σ1 − σ3 (MPa)")


def mark_crack_stresses(ax, curve, lateral_strains: int) -> None:
    """CI (onset of cracking) and CD (reversal of the volumetric strain over `lateral_strains`
    lateral strains) as dotted lines, when the curve has its column of broken bonds
    (`rockcal.labtests.damage`)."""
    curve = np.asarray(curve, float)
    if curve.ndim != 2 or curve.shape[1] < 4 or len(curve) < 3:
        return
    found = crack_stresses(*curve[:, :4].T, lateral_strains)
    for name, stress, colour in (("CI", found.ci_MPa, "tab:orange"), ("CD", found.cd_MPa, "tab:red")):
        ax.axhline(stress, color=colour, ls=":",
                   label=f"{name} {stress:.0f} MPa ({stress / found.peak_MPa:.2f} of the peak)")


def confined_curves(runs: list[tuple[dict, np.ndarray]], path: Path, title: str) -> None:
    """The curves of a series of confined compression runs, (responses, curve) each: q against
    the axial strain (solid) and the lateral strain (dashed, shown negative), one colour per
    confinement."""
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for (responses, curve), colour in zip(runs, plt.rcParams["axes.prop_cycle"].by_key()["color"] * 4):
        label = f"σ3 {responses['confinement_MPa']:g} MPa: peak σ1 {responses['sigma1_MPa']:.0f} MPa"
        ax.plot(100 * curve[:, 0], curve[:, 2], color=colour, label=label)
        ax.plot(-100 * curve[:, 1], curve[:, 2], color=colour, ls="--", lw=0.8)
    _finish(fig, ax, "strain (%)  (axial solid, lateral dashed, shown negative)",
            "deviatoric stress q = σ1 − σ3 (MPa)", title, path)


def load_displacement(curve, path: Path, title: str, rig=None) -> None:
    """Load against displacement (mm), peak marked; the load in the `rig`'s unit (kN per m of
    thickness in 2D, kN in 3D: `rockcal.labtests.rig.Rig.load_unit`; no rig: 2D's)."""
    unit = "kN/m" if rig is None else rig.load_unit
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(curve[:, 0], curve[:, 1])
    _mark_peak(ax, curve[:, 0], curve[:, 1], f"peak {{:.2f}} {unit}")
    _finish(fig, ax, "displacement (mm)", "load (kN per m of thickness)" if unit == "kN/m" else f"load ({unit})",
            title, path)


def _mark_peak(ax, x, y, label: str) -> None:
    """The curve's peak as a red dot, labelled `label` with the peak's value in its {}."""
    k = y.argmax()
    ax.plot(x[k], y[k], "o", color="tab:red", label=label.format(y[k]))


def _finish(fig, ax, xlabel: str, ylabel: str, title: str, path: Path) -> None:
    """Labels, grid and legend of a curve plot; save it and free the figure."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:  # an empty legend box says nothing, and warns
        ax.legend()
    _save(fig, path)


RESPONSE_LABELS = {"E_GPa": "E (GPa)", "nu": "Poisson's ratio ν (–)", "ucs_MPa": "UCS (MPa)",
                   "K_IC_MPa_sqrt_m": "K_IC (MPa·m^0.5)"}
PARAMETER_LABELS = {"E_c": "E_c (GPa)", "Ebar_c": "Ē_c (GPa)", "kn_ks": "kn/ks (–)",
                    "knbar_ksbar": "k̄n/k̄s (–)", "sigma_c": "σ_c (MPa)", "tau_c": "τ_c (MPa)",
                    "mu": "μ (–)", "lambda": "λ (–)", "density": "density (kg/m³)",
                    "damping": "damping (–)"}


def _label(name: str, labels: dict) -> str:
    """The axis label of a response or parameter, with its unit when known."""
    return labels.get(name, name)


def range_bars(R: dict[str, dict[str, float]], chosen: list[str], path: Path, note: str = "") -> None:
    """Range R of each factor per response (R[response][factor]); chosen factors in colour."""
    fig, axes = plt.subplots(1, len(R), figsize=(3.6 * len(R), 3.8), squeeze=False)
    for ax, (response, by_factor) in zip(axes[0], R.items()):
        factors = list(by_factor)
        top = max(factors, key=by_factor.get)
        colours = ["tab:orange" if f in chosen else "0.7" for f in factors]
        bars = ax.bar([_label(f, PARAMETER_LABELS) for f in factors], list(by_factor.values()),
                      color=colours, edgecolor=["black" if f == top else "none" for f in factors])
        ax.bar_label(bars, fmt="%.3g", fontsize=7)
        ax.set_title(f"{_label(response, RESPONSE_LABELS)}: largest R {top}", fontsize=9)
        ax.set_ylabel(f"range R of {_label(response, RESPONSE_LABELS)}", fontsize=8)
        ax.tick_params(axis="x", labelrotation=45, labelsize=7)
        ax.grid(axis="y", alpha=0.3)
    fig.suptitle(f"Range analysis{note} (orange: parameters inverted; outlined: largest R)")
    _save(fig, path)


def parity(points: dict[str, dict[str, tuple[list, list]]], tolerance: float, path: Path,
           x: str = "DEM", y: str = "surrogate", title: str = "Surrogate against DEM") -> None:
    """Surrogate prediction against DEM value per response (points[response][label] = (dem,
    predicted)), with the 1:1 line and the ±tolerance band; `x`, `y` and `title` name the two
    sources when they are others (rockcal against PFC2D, say)."""
    fig, axes = plt.subplots(1, len(points), figsize=(3.8 * len(points), 3.9), squeeze=False)
    for ax, (response, series) in zip(axes[0], points.items()):
        values = [v for dem, pred in series.values() for v in (*dem, *pred)]
        low, high = min(values), max(values)
        pad = 0.1 * (high - low) + 1e-9 * max(abs(low), abs(high), 1.0)
        line = [low - pad, high + pad]
        ax.plot(line, line, color="black", lw=0.8, label="1:1")
        ax.fill_between(line, [(1 - tolerance) * v for v in line], [(1 + tolerance) * v for v in line],
                        color="tab:green", alpha=0.15, label=f"±{100 * tolerance:g} %")
        for (label, (dem, pred)), marker in zip(series.items(), "os^"):
            ax.plot(dem, pred, marker, ls="none", label=label)
        ax.set_xlabel(f"{x} {_label(response, RESPONSE_LABELS)}", fontsize=8)
        ax.set_ylabel(f"{y} {_label(response, RESPONSE_LABELS)}", fontsize=8)
        ax.set_title(_label(response, RESPONSE_LABELS), fontsize=9)
        ax.set_xlim(line)
        ax.set_ylim(line)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(title)
    _save(fig, path)


def aco_convergence(history_fun, history_x, names: list[str], path: Path, title: str) -> None:
    """Best objective (log scale) and best value of each parameter per ACO iteration."""
    fig, axes = plt.subplots(1 + len(names), 1, figsize=(6, 2 + 1.6 * len(names)), sharex=True)
    generation = range(1, len(history_fun) + 1)
    axes[0].semilogy(generation, history_fun)
    axes[0].set_ylabel("best objective F")
    axes[0].set_title(title)
    for j, (ax, name) in enumerate(zip(axes[1:], names)):
        ax.plot(generation, [x[j] for x in history_x], color=f"C{j + 1}")
        ax.set_ylabel(_label(name, PARAMETER_LABELS), fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("ACO iteration")
    _save(fig, path)


def loop_errors(errors: dict[str, list], tolerance: float, path: Path) -> None:
    """Relative error (%) of the verified DEM responses per loop iteration (None: run failed),
    with the ±tolerance band."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    n = max(len(v) for v in errors.values())
    ax.axhspan(-100 * tolerance, 100 * tolerance, color="tab:green", alpha=0.15,
               label=f"±{100 * tolerance:g} %")
    ax.axhline(0, color="black", lw=0.8)
    for response, values in errors.items():
        y = [float("nan") if v is None else 100 * v for v in values]
        ax.plot(range(1, n + 1), y, "o-", label=_label(response, RESPONSE_LABELS))
    ax.set_xticks(range(1, n + 1))
    _finish(fig, ax, "loop iteration (DEM verification)", "(simulated − target) / target (%)",
            "Verified responses against the targets", path)


def trade_off(errors, pareto: list[int], best: list[float] | None, responses: list[str], tolerance: float,
              path: Path) -> None:
    """Two responses' relative errors (%) at every DEM run of the search, their Pareto front
    (the runs no other beats in both) and the best compromise (None: not verified in both), with
    the tolerance box."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    e = 100 * np.asarray(errors, float).reshape(-1, 2)
    t = 100 * tolerance
    ax.add_patch(plt.Rectangle((-t, -t), 2 * t, 2 * t, color="tab:green", alpha=0.15,
                               label=f"both within ±{tolerance * 100:g} %"))
    ax.plot(e[:, 0], e[:, 1], "o", color="0.6", label="DEM runs of the search")
    ax.plot(e[pareto, 0], e[pareto, 1], "o-", color="tab:red", label="Pareto front (|errors|)")
    if best is not None:
        ax.plot(100 * best[0], 100 * best[1], "k*", ms=12, label="best compromise")
    ax.axhline(0, color="black", lw=0.8)
    ax.axvline(0, color="black", lw=0.8)
    first, second = (_label(r, RESPONSE_LABELS).split(" (")[0] for r in responses)
    _finish(fig, ax, f"{first}: (simulated − target) / target (%)",
            f"{second}: (simulated − target) / target (%)", "The trade-off between two targets", path)


def calibrated_curve(curve, measured, path: Path, title: str, lateral_strains: int) -> None:
    """Simulated axial and lateral stress–strain curves (curve columns: axial strain, lateral
    strain, stress MPa) and the measured axial curve (strain, stress MPa) when given; CI and CD
    read over the specimen's `lateral_strains` lateral strains (`mark_crack_stresses`)."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(100 * curve[:, 0], curve[:, 2], label="simulated, axial")
    ax.plot(-100 * curve[:, 1], curve[:, 2], ls="--", label="simulated, lateral")
    if measured is not None:
        ax.plot(100 * measured[:, 0], measured[:, 1], "k.", ms=3, label="measured, axial")
    mark_crack_stresses(ax, curve, lateral_strains)
    _finish(fig, ax, "strain (%)  (lateral shown negative)", "axial stress (MPa)", title, path)


def parameter_draws(samples, names: list[str], bounds: dict, identified: dict, path: Path,
                    title: str = "Identified parameters, one point per drawn target set") -> None:
    """Corner plot of points in parameter space (the parameters solved for each drawn target
    set, the points that meet the sheet): histograms on the diagonal, pairs below it, the
    search box as the axes' limits and the identified point."""
    x = np.asarray(samples, float)
    n = len(names)
    fig, axes = plt.subplots(n, n, figsize=(2.6 * n, 2.6 * n), squeeze=False)
    for i in range(n):
        for j in range(n):
            ax = axes[i][j]
            if j > i:
                ax.set_axis_off()
                continue
            if i == j:
                ax.hist(x[:, i], bins=20, range=bounds[names[i]], color="tab:blue", alpha=0.7)
                ax.axvline(identified[names[i]], color="black", lw=1)
                ax.set_yticks([])
            else:
                ax.plot(x[:, j], x[:, i], ".", ms=3, alpha=0.5)
                ax.plot(identified[names[j]], identified[names[i]], "k+", ms=10)
                ax.set_ylim(bounds[names[i]])
            ax.set_xlim(bounds[names[j]])
            ax.tick_params(labelsize=7)
            if i == n - 1:
                ax.set_xlabel(names[j], fontsize=8)
            if j == 0 and i > 0:
                ax.set_ylabel(names[i], fontsize=8)
    fig.suptitle(title, fontsize=10)
    _save(fig, path)


def plot_envelope(sigma3_MPa, sigma1_MPa, path: Path, title: str = "Strength envelope") -> None:
    """The peaks (sigma3, sigma1) with the Mohr-Coulomb line and the Hoek-Brown curve (said
    absent where Hoek's regression gives no intact envelope through the peaks)."""
    s3, s1 = check_peaks(sigma3_MPa, sigma1_MPa)
    mc = fit_mohr_coulomb(s3, s1)
    try:
        hb = fit_hoek_brown(s3, s1)
    except InputError as exc:
        hb, no_hb = None, exc.problem.split(":")[0]
    x = np.linspace(0.0, 1.1 * s3.max(), 100)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(s3, s1, "o", color="k", label="peaks")
    ax.plot(x, mc.sigma1(x), label=f"Mohr-Coulomb: φ {mc.phi_deg:.1f}°, c {mc.c_MPa:.1f} MPa "
                                   f"(R² {mc.r2:.3f})")
    if hb is None:
        ax.plot([], [], " ", label=f"Hoek-Brown: none ({no_hb})")
    else:
        ax.plot(x, hb.sigma1(x), "--", label=f"Hoek-Brown: m_i {hb.m_i:.1f}, σ_ci {hb.sigma_ci_MPa:.0f} "
                                             f"MPa (r² {hb.r2:.3f})")
    ax.set_xlabel("confinement σ3 (MPa)")
    ax.set_ylabel("peak σ1 (MPa)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, path)


def strength_envelope(runs: list[tuple[dict, np.ndarray]], path: Path, title: str) -> None:
    """A series of confined compression runs' peaks and their envelope (`plot_envelope`)."""
    plot_envelope([r["confinement_MPa"] for r, _ in runs], [r["sigma1_MPa"] for r, _ in runs], path, title)


def plot_crack_stresses(curve, path, title: str = "Compression test", lateral_strains: int = 1) -> None:
    """Two panels of a compression curve up to its peak (columns: axial, lateral strain, q MPa,
    bonds broken): q against the axial, lateral (shown negative) and volumetric strain (over
    `lateral_strains` lateral strains: 2D's areal strain with one), and the bonds broken and the
    crack volumetric strain against q; CI (both readings) and CD marked."""
    axial, lateral, q, broken = np.asarray(curve, float)[:, :4].T
    found = crack_stresses(axial, lateral, q, broken, lateral_strains)
    peak = int(np.argmax(q))
    axial, lateral, q, broken = axial[:peak + 1], lateral[:peak + 1], q[:peak + 1], broken[:peak + 1]
    _, _, crack = crack_strain(axial, lateral, q, lateral_strains=lateral_strains)
    volumetric = VOLUMETRIC_NAME[lateral_strains]
    marks = (("CI", found.ci_MPa, "tab:orange"),
             ("CI (crack strain)", found.ci_strain_MPa, "tab:purple"),
             ("CD", found.cd_MPa, "tab:red"))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    left.plot(100 * axial, q, label="axial")
    left.plot(-100 * lateral, q, label="lateral")
    left.plot(100 * volumetric_strain(axial, lateral, lateral_strains), q, label=volumetric)
    right.plot(q, broken, color="k", label="bonds broken")
    twin = right.twinx()
    twin.plot(q, 1e6 * crack.strain, color="tab:purple", lw=0.8, label=f"crack {volumetric} strain")
    twin.set_ylabel(f"crack {volumetric} strain (10⁻⁶)")
    for name, stress, colour in marks:
        text = f"{name} {stress:.0f} MPa ({stress / found.peak_MPa:.2f})"
        left.axhline(stress, color=colour, ls=":", label=text)
        right.axvline(stress, color=colour, ls=":", label=text)
    left.set_xlabel("strain (%)  (lateral shown negative)")
    left.set_ylabel("deviatoric stress q (MPa)")
    right.set_xlabel("deviatoric stress q (MPa)")
    right.set_ylabel("bonds broken")
    for ax in (left, right):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    fig.suptitle(title)
    _save(fig, path)


def _save(fig, path: Path) -> None:
    """Lay out, save (whole, never through a link: `save_figure`) and free a figure."""
    fig.tight_layout()
    save_figure(fig, path, dpi=150)
    plt.close(fig)
