"""State-space models: the closed-loop vehicles of the mode-signature paper (47th IEEE CDC, Cancún, 2008) and their augmented filter models (its eq 44); the sensor and motion
models of the track-existence and manoeuvre scenarios."""
