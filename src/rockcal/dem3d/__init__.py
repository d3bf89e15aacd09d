"""A 3D bonded-particle engine: PFC3D's spheres, linear contact and linear parallel bond.

Modules, one idea each: `state` (the spheres' arrays), `laws` (the contact and bond laws),
`fused` (the fused multiply-add the laws are written with), `bonds` (the bonded pairs' state),
`forces` (the compiled pair loops), `neighbours` (the cell grid and pair list), `walls` (planar
walls: vessel faces, platens), `simulate` (time step, density scaling, the stepping loop),
`clumps` (a clump's mass properties) and `clump_motion` (rigid clumps of pebbles).
It implements the engine protocol (`rockcal.engine`) as the 2D engine does: its specimens are
made by `rockcal.specimens3d`, a material's 3D laws come from its module (`rockcal.materials`)
and the lab tests run on it through the 3D rig (`rockcal.labtests.rig`).
"""

ENGINE_VERSION_3D = 4  # part of every stored 3D run's key: raise it when the 3D engine's numbers change
