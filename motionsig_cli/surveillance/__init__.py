"""The surveillance analyses of ATC-10 (Schneider, Stiglitz & Eckberg, *Surveillance Aspects of the Advanced Air
Traffic Management System*, MIT Lincoln Laboratory, 1972): jamming bounds (§2), multiple-access noise (§3),
satellite multilateration (§4)."""
