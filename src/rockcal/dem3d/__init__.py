"""A 3D bonded-particle engine: PFC3D's spheres, linear contact, linear parallel bond and flat
joint.

Modules, one idea each: `state` (the spheres' arrays), `laws` (the contact and bond laws),
`fused` (the fused multiply-add the laws are written with), `bonds` (the parallel bonds'
state), `forces` (the compiled pair loops), `flat_joint` (the flat joint's law, state and
loop), `neighbours` (the cell grid and pair list), `walls` (planar walls: vessel faces,
platens; a cylinder), `simulate` (time step, density scaling, the stepping loop), `clumps` (a
clump's mass properties) and `clump_motion` (rigid clumps of pebbles).
It implements the engine protocol (`rockcal.engine`) as the 2D engine does: its specimens are
made by `rockcal.specimens3d`, a material's 3D laws come from its module (`rockcal.materials`)
and the lab tests run on it through the 3D rig (`rockcal.labtests.rig`).
"""

ENGINE_VERSION_3D = 4  # part of every stored 3D run's key: raise it when the 3D engine's numbers change
