"""Detectors: the LMP mode detector (eq 52 of the mode-signature paper) with its FFT fast path, Wald's
sequential test and the track-existence scores, GLR/MLR manoeuvre detection."""
