"""Rig → model pieces → assembled system: the beam, hybrid and solid models of a rig, its unit loads, and the
checks made before a model is solved."""
