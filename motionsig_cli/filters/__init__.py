"""Estimators on arrays, batched over a leading candidate axis (and a trial axis for the means)."""
