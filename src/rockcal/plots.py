"""Figures a rock engineer expects; matplotlib without a display."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402


def crack_pattern(positions, radius, cracks: dict, path: Path, title: str) -> None:
    """The deformed specimen in grey with broken bonds: tension red, shear blue."""
    width_m = positions[:, 0].max() - positions[:, 0].min()
    height_m = positions[:, 1].max() - positions[:, 1].min()
    fig, ax = plt.subplots(figsize=(4 + 4 * width_m / max(height_m, width_m), 8 * height_m / max(height_m, width_m)))
    mm = positions * 1e3
    disks = EllipseCollection(2e3 * radius, 2e3 * radius, 0, units="xy", offsets=mm,
                              offset_transform=ax.transData, facecolors="0.85", edgecolors="0.6",
                              linewidths=0.2)
    ax.add_collection(disks)
    for mode, colour in (("tension", "tab:red"), ("shear", "tab:blue")):
        xy = cracks[mode] * 1e3
        ax.plot(xy[:, 0], xy[:, 1], "o", ms=2, color=colour, label=f"{mode} ({len(xy)})")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)


def stress_strain(curve, path: Path, title: str) -> None:
    """Axial stress against axial and lateral strain (%)."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(100 * curve[:, 0], curve[:, 2], label="axial")
    ax.plot(-100 * curve[:, 1], curve[:, 2], label="lateral")
    _finish(fig, ax, "strain (%)  (lateral shown negative)", "axial stress (MPa)", title, path)


def load_displacement(curve, path: Path, title: str) -> None:
    """Load (kN per m of thickness) against displacement (mm), peak marked."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(curve[:, 0], curve[:, 1])
    k = curve[:, 1].argmax()
    ax.plot(curve[k, 0], curve[k, 1], "o", color="tab:red", label=f"peak {curve[k, 1]:.2f} kN/m")
    _finish(fig, ax, "displacement (mm)", "load (kN per m of thickness)", title, path)


def _finish(fig, ax, xlabel: str, ylabel: str, title: str, path: Path) -> None:
    """Labels, grid and legend of a curve plot; save it and free the figure."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
