"""Scenarios and Monte Carlo experiments (seeded per trial; results independent of batching)."""
