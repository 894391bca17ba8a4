"""Detectors: the LMP mode detector (seed 000 eq 52) and, later, SPRT/SLRT and GLR/MLR tests."""
