"""The mode-signature paper (47th IEEE CDC, 2008): the LMP mode detector's studies, records and calibration."""
