"""The inverse procedure: its declared steps and their state (`steps`), the forward runs of a
parameter set (`points`), the runs at the identified point (`final`), what the campaign
calibrates against (`goals`), the verdict when targets conflict (`verdict`) and the result
(`result`)."""

from rockcal.campaign.procedure.steps import calibrate

__all__ = ["calibrate"]
