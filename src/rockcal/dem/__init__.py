"""A 2D bonded-particle engine: PFC2D's disks (and rigid clumps of them), linear contact,
linear parallel bond and flat joint.

Modules, one idea each: `simulate` (the state, time step, density scaling, the stepping loop),
`laws` (the contact and parallel-bond laws), `flatjoint` (the flat joint's), `bonded` (a
step's bonded phase, whatever the law), `neighbours` (the cell grid, the pair list, the pairs
within an installation gap), `clumps` and `clump_motion` (rigid clumps), `tasks`, `border`,
`atomics` and `cores` (how the threads share a step, which the 3D engine shares too) and
`measure` (readings of a specimen). It implements the engine protocol (`rockcal.engine`); its
specimens are made by `rockcal.specimens`.
"""
