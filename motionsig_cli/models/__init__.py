"""State-space models: the closed-loop vehicles of seed 000 and the augmented filter models of eq 44."""
