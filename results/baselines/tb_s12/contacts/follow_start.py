"""For each contact in a tbinstr.py record: when the follow stretch that holds it began (the last
switch from motion to goal into the approach / boundary following), where, on which side, how
long the approach lasted, the blocking point, and the jump flags of the motion-to-goal cycles just
before (1: toward an endpoint at a rho jump, 0: at a free bin, -1: goal direction free).

usage: python follow_start.py REC.npz ...
"""
import sys

import numpy as np


def main() -> None:
    for path in sys.argv[1:]:
        z = np.load(path)
        R, C = z["rec"], z["contacts"].reshape(-1, 2)
        t, code, jump = R[:, 0], R[:, 4].astype(int), R[:, 5].astype(int)
        for tc, _ in C:
            i = int(np.searchsorted(t, tc))
            j = i
            while j > 0 and code[j - 1] >= 2:  # back to the cycle following began
                j -= 1
            a = j
            while a < i and code[a] == 2:
                a += 1
            strict = bool(np.any(code[j:i + 1] == 4))
            print(f"{path} contact {tc:.1f}s: follow began {t[j]:.1f}s ({tc - t[j]:.1f}s before) at "
                  f"({R[j, 1]:.2f},{R[j, 2]:.2f}) side {int(R[j, 6])}; approach {t[a] - t[j]:.1f}s; "
                  f"blocking ({R[j, 9]:.2f},{R[j, 10]:.2f}); motion-to-goal just before: jump flags "
                  f"{jump[max(0, j - 6):j].tolist()}; strict lap in between {strict}")


if __name__ == "__main__":
    main()
