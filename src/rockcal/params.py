"""Micro-parameters of the bonded-particle model, in the units rock engineers quote them.

Names follow PFC2D's linear + linear parallel bond model (Potyondy & Cundall 2004): E_c and
kn_ks for the linear contact; Ebar_c, knbar_ksbar, lambda, sigma_c, tau_c for the parallel bond,
and PFC 5's bond options: per-bond normal spreads sigma_c_sd, tau_c_sd (pb_ten, pb_coh sd; or
sigma_c_cv, tau_c_cv, the sd as a fraction of the mean, which Potyondy & Cundall quote and which
stays meaningful while a calibration moves the mean),
friction angle phi_b (pb_fa; shear strength tau_c - sigma tan phi_b) and moment contribution
factor mcf (pb_mcf); their defaults give Potyondy & Cundall's constant-strength bond.
Defaults are the source study's identified granite values (E_c 21.65 GPa, kn/ks 1.9,
sigma_c 36.55 MPa) and its fixed ones (tau_c 90 MPa, mu 0.5, lambda 1).
"""

from __future__ import annotations

import math
from typing import ClassVar

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from rockcal.errors import InputError, from_validation_error

GPa = 1e9
MPa = 1e6


class MicroParams(BaseModel):
    """BPM micro-parameters (GPa, MPa, kg/m³; others dimensionless)."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)

    E_c: float = Field(21.65, ge=0, le=1e4, description="contact effective modulus, GPa (0 = bonds only)")
    Ebar_c: float | None = Field(None, ge=0, le=1e4, description="bond effective modulus, GPa (default E_c)")
    kn_ks: float = Field(1.9, gt=0, le=1e3, description="contact normal-to-shear stiffness ratio")
    knbar_ksbar: float | None = Field(None, gt=0, le=1e3, description="bond stiffness ratio (default kn_ks)")
    sigma_c: float = Field(36.55, gt=0, le=1e5, description="bond tensile strength (mean), MPa")
    tau_c: float = Field(90.0, gt=0, le=1e5, description="bond cohesion (mean shear strength), MPa")
    sigma_c_sd: float = Field(0.0, ge=0, le=1e5, description="bond tensile strength sd, MPa")
    tau_c_sd: float = Field(0.0, ge=0, le=1e5, description="bond cohesion sd, MPa")
    sigma_c_cv: float = Field(0.0, ge=0, le=10, description="bond tensile strength sd / mean")
    tau_c_cv: float = Field(0.0, ge=0, le=10, description="bond cohesion sd / mean")
    phi_b: float = Field(0.0, ge=0, lt=90, description="bond friction angle, degrees")
    mcf: float = Field(1.0, ge=0, le=1, description="bond moment contribution factor")
    mu: float = Field(0.5, ge=0, le=10, description="contact friction coefficient")
    lambda_: float = Field(1.0, gt=0, le=1, alias="lambda", description="bond radius multiplier")
    density: float = Field(2622.0, gt=0, le=1e5, description="particle density, kg/m³")
    damping: float = Field(0.7, ge=0, lt=1, description="local damping coefficient")

    @model_validator(mode="after")
    def _fill_bond_defaults(self):
        if self.Ebar_c is None:
            object.__setattr__(self, "Ebar_c", self.E_c)
        if self.knbar_ksbar is None:
            object.__setattr__(self, "knbar_ksbar", self.kn_ks)
        if self.E_c == 0 and self.Ebar_c == 0:
            raise ValueError("E_c and Ebar_c cannot both be 0")
        for name in ("sigma_c", "tau_c"):
            if getattr(self, name + "_sd") and getattr(self, name + "_cv"):
                raise ValueError(f"{name}_cv: set {name}_sd or {name}_cv, not both")
        return self

    @property
    def strength_sds(self) -> tuple[float, float]:
        """The sd (MPa) of the bond tensile strength and cohesion: PFC's pb_ten, pb_coh sd."""
        return (self.sigma_c_sd or self.sigma_c_cv * self.sigma_c,
                self.tau_c_sd or self.tau_c_cv * self.tau_c)

    def key(self) -> dict[str, float]:
        """All values by their user names (for storage and reports)."""
        return self.model_dump(by_alias=True)

    CONTACT_MODULUS: ClassVar[str] = "E_c"  # the linear contacts' modulus (GPa), by name

    @property
    def bonded_modulus_GPa(self) -> float:
        """A bonded pair's modulus, contact and parallel bond side by side, E_c + λ Ē_c: an
        estimate of the rock's, for its wave speed."""
        return self.E_c + self.lambda_ * self.Ebar_c


NAMES = tuple(MicroParams.model_fields[f].alias or f for f in MicroParams.model_fields)


def make_params(values: dict[str, float]) -> MicroParams:
    """Validate a mapping of user names to values; any mistake raises InputError naming the field."""
    unknown = sorted(set(values) - set(NAMES))
    if unknown:
        raise InputError(unknown[0], f"unknown parameter; known: {', '.join(NAMES)}")
    for name, value in values.items():
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
            raise InputError(name, f"must be a finite number, got {value!r}")
    try:
        return MicroParams(**values)
    except ValidationError as exc:
        raise from_validation_error(exc) from None


def parse_assignments(items: list[str]) -> dict[str, float]:
    """Parse CLI `NAME=VALUE` strings into numbers."""
    values: dict[str, float] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise InputError("--set", f"expected NAME=VALUE, got {item!r}")
        try:
            values[name] = float(text)
        except ValueError:
            raise InputError(name, f"not a number: {text.strip()!r}") from None
    return values
