"""3D specimens, made as PFC3D's material genesis makes them: `genesis` (the sphere cloud, the
floaters, the bonds), `packing` (grains scaled to the material pressure) and `specimen`
(cuboids, and the cylinders and disks carved from them, cached on disk)."""
