"""The discrepancy workflow: locate where model and measurement disagree, name the missing
physical effect, add it to the rig, and show the gap shrink.

Data flow: measured file → :mod:`measured` → observation vector; rig + effect library
(:mod:`rvcoax.geometry.effects`) → :mod:`responses` (each candidate's predicted change of every
observation) → :mod:`locate` (noise, χ², structure) → :mod:`identify` (fits, forward/backward
selection by BIC, ambiguity) → :mod:`workflow` (confirmation with the true model, rig file,
report).
"""
