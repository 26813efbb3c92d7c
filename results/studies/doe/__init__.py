"""Orthogonal experiments: standard arrays, range analysis and ANOVA, second-order regression, rig studies."""
