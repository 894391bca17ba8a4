"""Signals (seed 000 §II.A): LFSR m-sequences, Gold codes, GPS C/A codes, mode signatures.

Bits are ``uint8`` arrays of 0/1, chip 0 first. Bipolar chips follow the seed's BPSK mapping
(ρ0 = −1 for bit 0, ρ1 = +1 for bit 1).
"""
