"""A parallel-bonded material in 3D: the 2D micro-parameters (`rockcal.materials.parallel_bond
.MicroParams`, PFC's names: E_c, kn_ks, Ebar_c, knbar_ksbar, sigma_c, tau_c and their spreads,
phi_b, mcf, lambda, mu, density, damping) mapped to the 3D engine's law constants and bond
strengths. The names mean what they mean in PFC3D; a rock's values differ from its PFC2D ones.
"""

from __future__ import annotations

import math

import numpy as np

from rockcal.dem3d.laws import Laws
from rockcal.dem3d.simulate import State, assemble_state
from rockcal.dem3d.walls import Walls
from rockcal.materials.parallel_bond import MicroParams, bond_strengths
from rockcal.materials.units import GPa


def laws_of(params: MicroParams) -> Laws:
    """The 3D law constants (SI) of the micro-parameters."""
    return Laws(E_c=params.E_c * GPa, ks_per_kn=1.0 / params.kn_ks, mu=params.mu,
                Ebar_c=params.Ebar_c * GPa, ksbar_per_knbar=1.0 / params.knbar_ksbar,
                lam=params.lambda_, tan_phi=math.tan(math.radians(params.phi_b)),
                mcf=params.mcf)


def wall_modulus_pa(params: MicroParams) -> float:
    """The modulus of the walls' contacts: the material's contact modulus (FISHTank's
    platens), or its bond modulus if the contacts have none (as in 2D)."""
    return (params.E_c if params.E_c > 0 else params.Ebar_c) * GPa


def material_state(params: MicroParams, specimen, walls: Walls | None = None) -> State:
    """The specimen at rest with the material's laws, each bond's strengths drawn at its
    uniform draws (`bond_strengths`: truncated normal), between `walls`."""
    ten, coh = bond_strengths(params, np.asarray(specimen.bond_draws), len(specimen.bonds))
    return assemble_state(specimen.pos, specimen.radius, specimen.bonds, params.density,
                          laws_of(params), damping=params.damping, ten=ten, coh=coh, walls=walls)
