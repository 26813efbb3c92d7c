"""The ranges that every reader of the analysis settings checks (--alpha/--pool-below-F and a study file's [study])."""

__all__ = ["ALPHA_RANGE", "POOL_BELOW_F_RANGE"]

ALPHA_RANGE = (0.0, 0.5)  # exclusive: a significance level of 0.5 or more tests nothing
POOL_BELOW_F_RANGE = (0.0, 1000.0)  # inclusive: pooling sources with F below 1000 already pools every real effect
