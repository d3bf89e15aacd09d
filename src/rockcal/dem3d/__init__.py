"""A 3D bonded-particle engine: PFC3D's spheres, linear contact and linear parallel bond.

Modules, one idea each: `state` (the spheres' arrays), `laws` (the contact and bond laws),
`bonds` (the bonded pairs' state), `forces` (the compiled pair loops), `neighbours` (the cell
grid and pair list) and `simulate` (time step, density scaling, the stepping loop).
"""
