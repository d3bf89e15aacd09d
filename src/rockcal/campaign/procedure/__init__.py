"""The inverse procedure: its declared steps (`steps`) and their state (`state`), the forward
runs of a parameter set (`points`) and the rounding of the points run (`rounding`), the runs at
the identified point (`final`), what the campaign calibrates against (`goals`), the verdict
when targets conflict (`verdict`) and the result (`result`)."""

from rockcal.campaign.procedure.steps import calibrate

__all__ = ["calibrate"]
