"""The ATC-10 surveillance analyses (MIT Lincoln Lab, 1972): jamming bounds (§2), multiple-access
noise (§3), satellite multilateration (§4)."""
