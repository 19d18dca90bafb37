#!/usr/bin/env python3
"""Cost model of a distributed heart beat (docs/scaling.md, "A cost model for a cluster").

The time of one beat on P ranks (one core each) is modelled as

  T(P) = imbalance * (S_m * n * c_m + S_e * n * c_e)                       compute
       + S_m * (X_m * (m * alpha + g * b_m / beta) + R_m * 2 * alpha * log2 P)  mechanics messages
       + S_e * (X_e * (m * alpha + g * b_e / beta) + R_e * 2 * alpha * log2 P)  EP messages

with n = N / P owned particles, g = gamma * n^(2/3) ghosts per rank, m neighbour ranks, S_m and S_e
the mechanics sub-steps and EP steps of a beat, X the halo exchanges and R the all-reduces per step,
b the bytes per ghost and exchange. Every input is printed with the output; the measured ones are
those of docs/scaling.md and docs/electromechanics.md. Usage: scripts/scaling_model.py
"""
import math

# Measured (this machine, the default heart at dp 2 mm: 12,444 particles, 13,300 mechanics
# sub-steps and about 8,400 EP steps of 0.1 ms per beat; mechanics 83 s and the rest 58 s per beat
# on 2 threads; the TLSPH step of the myocardium cube runs 1.76x faster on 2 threads than on 1).
HEART_PARTICLES_2MM = 12444
SUBSTEPS_2MM = 13300
EP_STEPS = 8400
THREAD_SPEEDUP = 1.76
C_MECH = 83.0 * THREAD_SPEEDUP / (SUBSTEPS_2MM * HEART_PARTICLES_2MM)  # core-s per particle-sub-step
C_EP = 58.0 * THREAD_SPEEDUP / (EP_STEPS * HEART_PARTICLES_2MM)        # core-s per particle-EP step

# The exchanges of the distributed systems (docs/scaling.md): TLSPH 2 halo exchanges per sub-step
# (positions 24 B, then F and P B0 144 B per ghost), monodomain 4 per EP step (the potential, 8 B,
# after each reaction half-step and in each of the 2 Heun stages of a diffusion step); all-reduces
# per sub-step: time step, two failure checks, largest acceleration, cavity volumes and pressures
# (6); per EP step: 2 failure checks.
X_M, B_M, R_M = 2, 168 / 2, 6  # (bytes averaged over the two exchanges)
X_E, B_E, R_E = 4, 8, 2

GAMMA = 18.0        # ghosts per owned^(2/3): an interior cube-shaped block, 3 layers on 6 faces
NEIGHBOURS = 12     # neighbour ranks of a block (RCB in 3D: 6 faces and some edges)
IMBALANCE = 1.05    # slowest rank over the mean (RCB balances counts, not cost)

NETWORKS = {
    # alpha [s] MPI latency per message; beta [B/s] bandwidth per rank (a node's link shared by
    # all its ranks, every halo byte assumed to leave the node)
    "InfiniBand HDR, 32 ranks per node": (1.5e-6, 25e9 / 32),
    "10 Gb Ethernet, 32 ranks per node": (20e-6, 1.25e9 / 32),
}


def beat_seconds(N, P, spacing_mm, alpha, beta):
    substeps = SUBSTEPS_2MM * (2.0 / spacing_mm)  # the acoustic step scales with the spacing
    n = N / P
    compute = (IMBALANCE if P > 1 else 1.0) * (substeps * n * C_MECH + EP_STEPS * n * C_EP)
    if P == 1:
        return compute, 0.0
    g = GAMMA * n ** (2.0 / 3.0)
    m = min(NEIGHBOURS, P - 1)
    tree = 2 * alpha * math.log2(P)
    messages = substeps * (X_M * (m * alpha + g * B_M / beta) + R_M * tree)
    messages += EP_STEPS * (X_E * (m * alpha + g * B_E / beta) + R_E * tree)
    return compute, messages


def main():
    print(f"c_mech = {C_MECH * 1e6:.3f} us, c_ep = {C_EP * 1e6:.3f} us per particle-step on one core")
    print(f"gamma = {GAMMA}, neighbours = {NEIGHBOURS}, imbalance = {IMBALANCE}")
    for label, (alpha, beta) in NETWORKS.items():
        print(f"\n{label}: alpha = {alpha * 1e6:.1f} us, beta = {beta / 1e9:.2f} GB/s per rank")
        print("| heart | ranks | owned per rank | ghosts per rank | compute | messages | beat | efficiency |")
        print("|---|---|---|---|---|---|---|---|")
        for N, spacing in ((8e5, 0.5), (6e6, 0.25)):
            serial, _ = beat_seconds(N, 1, spacing, alpha, beta)
            for P in (8, 16, 32, 64, 128, 256):
                compute, messages = beat_seconds(N, P, spacing, alpha, beta)
                total = compute + messages
                n = N / P
                print(f"| {N:.0e} ({spacing} mm) | {P} | {n:,.0f} | {GAMMA * n ** (2 / 3):,.0f} | {compute:,.0f} s | "
                      f"{messages:,.1f} s | {total / 60:,.1f} min | {serial / (P * total) * 100:.0f} % |")


if __name__ == "__main__":
    main()
