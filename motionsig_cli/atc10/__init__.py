"""MIT Lincoln Laboratory ATC-10: jamming bounds, multiple-access ROC, satellite tracking and multilateration."""
