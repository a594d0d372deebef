#!/usr/bin/env python3
"""How much a camera's frame-to-frame step changes from one frame to the next, for the
live estimate and for the ground truth of the same frames.

A constant-velocity prediction is as good as the velocity it extrapolates. This prints,
per axis of the camera frame, the rms change of the step (translation in mm, rotation
vector in deg) between consecutive tracked frames, for the estimate (tracking.csv's live
poses) and for the ground truth at the same stamps, and the correlation of the two
(doc/odometry.md, twenty-seventh round: Bonn's true step changes by 0.3-0.4 mm, the
estimate's by 8-20 mm). For the ground truth it also prints the lag-1 autocorrelation
of the changes and an upper bound of their part that is not the motion capture's white
pose noise (twenty-eighth round: Bonn's rotation changes are that noise).

  gmc-rgbd-mapping config/bonn.ini DATA --out R --set Output.tracking_log=true
  gmc-eval --gt DATA/groundtruth.txt --est R/trajectory_tum.txt --gt-frame bonn --gt-out R/gtc.txt
  scripts/step_changes.py R R/gtc.txt

The ground truth must be in the camera's frame (gmc-eval --gt-out); TUM's already is.
"""
import argparse
import bisect
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from window_eval import read_tum  # noqa: E402


def qmul(a, b):
    x1, y1, z1, w1 = a
    x2, y2, z2, w2 = b
    return (w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2, w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2)


def qinv(q):
    return (-q[0], -q[1], -q[2], q[3])


def rotate(q, v):
    return qmul(qmul(q, (v[0], v[1], v[2], 0.0)), qinv(q))[:3]


def rotation_vector_deg(q):
    if q[3] < 0:
        q = tuple(-c for c in q)
    s = math.sqrt(q[0] ** 2 + q[1] ** 2 + q[2] ** 2)
    if s < 1e-12:
        return (0.0, 0.0, 0.0)
    angle = math.degrees(2 * math.atan2(s, q[3]))
    return tuple(angle * c / s for c in q[:3])


def step(a, b):
    """(translation mm, rotation vector deg) of pose b in pose a's frame; poses (t, q)."""
    qi = qinv(a[1])
    t = rotate(qi, [1000.0 * (b[0][k] - a[0][k]) for k in range(3)])
    return t, rotation_vector_deg(qmul(qi, b[1]))


def read_poses(path):
    """A TUM trajectory as (stamp, position, quaternion xyzw)."""
    return [(v[0], tuple(v[1:4]), tuple(v[4:8])) for v in read_tum(path)]


def read_tracked(run):
    """(frame, stamp, pose) of the tracked frames of tracking.csv."""
    out = []
    with open(os.path.join(run, 'tracking.csv')) as f:
        for r in csv.DictReader(f):
            if r['state'] == 'tracking':
                pose = ((float(r['x']), float(r['y']), float(r['z'])),
                        (float(r['qx']), float(r['qy']), float(r['qz']), float(r['qw'])))
                out.append((int(r['frame']), float(r['stamp']), pose))
    return out


def interpolate(gt, stamps, t, max_gap=0.05):
    """The ground-truth pose at stamp t, interpolated between the samples around it
    (TUM's is 100 Hz: its nearest sample is up to 5 ms, 1.5 mm at 0.3 m/s, off the image's
    stamp, which alone would add millimetres to every step change); None outside it or
    across a gap of more than max_gap seconds."""
    i = bisect.bisect_left(stamps, t)
    if i < len(stamps) and stamps[i] == t:
        return gt[i][1:]
    if i == 0 or i == len(stamps) or stamps[i] - stamps[i - 1] > max_gap:
        return None
    (ta, pa, qa), (tb, pb, qb) = gt[i - 1], gt[i]
    w = (t - ta) / (tb - ta)
    if sum(x * y for x, y in zip(qa, qb)) < 0:
        qb = tuple(-c for c in qb)
    q = [(1 - w) * x + w * y for x, y in zip(qa, qb)]
    norm = math.sqrt(sum(c * c for c in q))
    return tuple((1 - w) * x + w * y for x, y in zip(pa, pb)), tuple(c / norm for c in q)


def step_pairs(tracked, gt):
    """Per pair of consecutive tracked frames with ground truth at both: (estimated step, true step)."""
    stamps = [g[0] for g in gt]
    pairs = []
    for (fa, ta, pa), (fb, tb, pb) in zip(tracked, tracked[1:]):
        ga, gb = interpolate(gt, stamps, ta), interpolate(gt, stamps, tb)
        if fb != fa + 1 or ga is None or gb is None:
            continue
        pairs.append((step(pa, pb), step(ga, gb)))
    return pairs


def rms(values):
    return math.sqrt(sum(v * v for v in values) / len(values)) if values else float('nan')


def correlation(a, b):
    n = len(a)
    if n < 2:
        return float('nan')
    ma, mb = sum(a) / n, sum(b) / n
    va, vb = sum((x - ma) ** 2 for x in a), sum((y - mb) ** 2 for y in b)
    return sum((x - ma) * (y - mb) for x, y in zip(a, b)) / math.sqrt(va * vb) if va > 0 and vb > 0 else float('nan')


def smooth_part_at_most(changes):
    """The rms of the part of a step-change series that is not white pose noise, at most.

    Motion capture adds white noise n of variance s2 to every pose; a step change then
    carries n[i+2] - 2 n[i+1] + n[i]: variance 6 s2 and lag-1 covariance -4 s2 (a lag-1
    autocorrelation of -2/3 for pure noise). A hand-held camera's own step changes vary
    smoothly (lag-1 covariance >= 0 at 30 Hz), so s2 >= -cov1 / 4 and the camera's part
    of the variance is at most var - 6 s2 <= var + 1.5 cov1."""
    n = len(changes)
    if n < 3:
        return float('nan')
    mean = sum(changes) / n
    var = sum((c - mean) ** 2 for c in changes) / n
    cov1 = sum((a - mean) * (b - mean) for a, b in zip(changes, changes[1:])) / (n - 1)
    return math.sqrt(max(0.0, var + 1.5 * min(0.0, cov1)))


def summary(pairs):
    """Per part (translation, rotation) and axis: rms step change of the estimate and of the
    truth, the correlation of the two changes, the truth's lag-1 autocorrelation and its
    part that is not white pose noise (at most). Only changes between consecutive pairs."""
    rows = []
    for part, unit in ((0, 'mm'), (1, 'deg')):
        for axis in range(3):
            est = [p[0][part][axis] for p in pairs]
            true = [p[1][part][axis] for p in pairs]
            d_est = [b - a for a, b in zip(est, est[1:])]
            d_true = [b - a for a, b in zip(true, true[1:])]
            rows.append(('translation' if part == 0 else 'rotation', 'xyz'[axis], unit, rms(d_est), rms(d_true),
                         correlation(d_est, d_true), correlation(d_true, d_true[1:]), smooth_part_at_most(d_true)))
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('run', help='output folder of gmc-rgbd-mapping with tracking.csv')
    p.add_argument('gt', help='ground truth in TUM format, in the camera frame')
    args = p.parse_args()
    for path in (os.path.join(args.run, 'tracking.csv'), args.gt):
        if not os.path.isfile(path):
            sys.exit('step_changes.py: %s: no such file' % path)
    pairs = step_pairs(read_tracked(args.run), read_poses(args.gt))
    if len(pairs) < 3:
        sys.exit('step_changes.py: %s: fewer than 3 consecutive tracked frames with ground truth' % args.run)
    print('%d consecutive tracked steps; rms change of the step from one frame to the next' % len(pairs))
    print('(ground truth: lag-1 autocorrelation of its changes, -0.67 for white pose noise alone, and the rms of '
          'its changes without that noise, at most)')
    for part, axis, unit, est, true, corr, lag1, smooth in summary(pairs):
        print('%-11s %s: estimate %7.3f %s, ground truth %7.3f %s, correlation %5.2f, lag-1 %5.2f, without noise '
              '<= %7.3f %s' % (part, axis, est, unit, true, unit, corr, lag1, smooth, unit))


if __name__ == '__main__':
    main()
