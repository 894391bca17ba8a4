"""Yao, Teng & Wu: manoeuvring-target tracking (IMM, GLR, MLR, CV), its studies, records and the EBPSK front end."""
