"""2D specimens, made as PFC2D's material genesis makes them: `genesis` (the grain cloud, the
floaters, the bonds within the installation gap), `packing` (grains scaled to the material
pressure), `clump_templates` and `clump_genesis` (PFC's clumped grains), `carving` (a disk or a
notched beam cut from a packing), `grain_limit` (what a machine can hold) and `specimen` (the
packings a lab test is cut from, cached on disk; `shipped/` holds those rockcal ships)."""
