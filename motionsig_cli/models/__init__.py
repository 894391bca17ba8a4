"""State-space models: the closed-loop vehicles of the mode-signature paper (LMP mode detection with
Gold-code signatures, IEEE CDC 2008) and their augmented filter models (its eq 44); the sensor and motion
models of the track-existence and manoeuvre scenarios."""
