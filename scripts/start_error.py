#!/usr/bin/env python3
"""How far a run ends from where it started, without any alignment.

The ATE aligns the whole estimate to the ground truth, so an offset that most of a run
carries (a re-anchored keyframe's guess, kept by every pose after it) is aligned away
and the stretch before it looks wrong instead. Here both trajectories are expressed
relative to their first pose, as the map is built: the position and rotation error of
every `--every`-th pose, and at the last pose.

  python3 scripts/start_error.py RUN/trajectory_tum.txt GROUNDTRUTH [--every 30]

GROUNDTRUTH holds camera poses: Bonn's holds the marker body, so convert it first with
`gmc-eval --gt GT --est RUN/trajectory_tum.txt --gt-frame bonn --gt-out GT_CAMERA`.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from error_profile import rotation  # noqa: E402
from window_eval import associate_pairs, read_tum  # noqa: E402


def pose(row):
    return rotation(row[4:8]), list(row[1:4])


def relative(a, b):
    """a^-1 * b for (R, t) pairs."""
    (Ra, ta), (Rb, tb) = a, b
    R = [[sum(Ra[k][i] * Rb[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    t = [sum(Ra[k][i] * (tb[k] - ta[k]) for k in range(3)) for i in range(3)]
    return R, t


def angle_deg(R):
    c = max(-1.0, min(1.0, (R[0][0] + R[1][1] + R[2][2] - 1) / 2))
    return math.degrees(math.acos(c))


def unaligned_errors(estimate, groundtruth):
    """(pose index, position error m, rotation error deg) of every estimated pose with a
    ground truth, both trajectories relative to their first pose; [] when none matches."""
    est, gt = read_tum(estimate), read_tum(groundtruth)
    pairs = associate_pairs([r[0] for r in est], gt)
    if not pairs:
        return []
    e0, g0 = pose(est[pairs[0][0]]), pose(pairs[0][1])
    rows = []
    for n, (i, g) in enumerate(pairs):
        E, G = relative(e0, pose(est[i])), relative(g0, pose(g))
        rows.append((n, math.dist(E[1], G[1]), angle_deg(relative(G, E)[0])))
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('estimate')
    p.add_argument('groundtruth')
    p.add_argument('--every', type=int, default=30)
    a = p.parse_args()
    rows = unaligned_errors(a.estimate, a.groundtruth)
    if not rows:
        sys.exit('start_error.py: no pose of %s matches the ground truth' % a.estimate)
    for n, position, turn in rows:
        if n % a.every == 0 or n == len(rows) - 1:
            print('pose %4d  position error %.4f m  rotation error %.2f deg' % (n, position, turn))
    print('last pose: %.4f m, %.2f deg; worst %.4f m' % (rows[-1][1], rows[-1][2], max(r[1] for r in rows)))


if __name__ == '__main__':
    main()
