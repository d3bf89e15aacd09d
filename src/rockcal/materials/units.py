"""The units rockcal's micro-parameters are quoted in, as SI factors: a value in GPa times GPa
is in Pa."""

GPa = 1e9
MPa = 1e6
MM = 1e-3
