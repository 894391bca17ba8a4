"""Signals (§II.A of the mode-signature paper, 47th IEEE CDC, Cancún, 2008):
LFSR m-sequences, Gold codes, GPS C/A codes, mode signatures.

Bits are ``uint8`` arrays of 0/1, chip 0 first. Bipolar chips follow the paper's BPSK mapping
(ρ0 = −1 for bit 0, ρ1 = +1 for bit 1).
"""
