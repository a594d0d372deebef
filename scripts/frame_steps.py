#!/usr/bin/env python3
"""Per-frame step of an estimated trajectory next to the ground truth's.

Median and p90 of |t_i - t_(i-1)| (mm) and of the rotation angle between consecutive
poses (deg), for the estimate and for the ground truth at the same stamps (nearest
within 0.02 s). A step far larger than the ground truth's is per-frame noise; the
figures of doc/odometry.md ("Per-frame translation noise") come from:

  ./build/bin/gmc-rgbd-mapping config/bonn.ini $D/bonn_crowd_240_389 --out /tmp/s \
      --set Output.map=false --set Dataset.max_frames=70
  python3 scripts/frame_steps.py /tmp/s/trajectory_tum.txt $D/bonn_crowd_240_389/groundtruth.txt
"""
import bisect
import math
import statistics
import sys


def read_tum(path):
    with open(path) as f:
        return [[float(v) for v in line.split()[:8]] for line in f if line.strip() and not line.startswith('#')]


def angle_deg(q1, q2):
    return 2 * math.degrees(math.acos(min(1.0, abs(sum(a * b for a, b in zip(q1, q2))))))


def main():
    est, gt = read_tum(sys.argv[1]), read_tum(sys.argv[2])
    stamps = [g[0] for g in gt]

    def nearest(s):
        i = bisect.bisect_left(stamps, s)
        j = min((k for k in (i - 1, i) if 0 <= k < len(gt)), key=lambda k: abs(stamps[k] - s))
        return gt[j] if abs(stamps[j] - s) <= 0.02 else None

    rows = []
    for a, b in zip(est, est[1:]):
        ga, gb = nearest(a[0]), nearest(b[0])
        if ga and gb:
            rows.append((1000 * math.dist(a[1:4], b[1:4]), 1000 * math.dist(ga[1:4], gb[1:4]),
                         angle_deg(a[4:8], b[4:8]), angle_deg(ga[4:8], gb[4:8])))
    if not rows:
        sys.exit('frame_steps.py: no consecutive estimated poses with ground truth within 0.02 s')

    def stat(k):
        v = sorted(r[k] for r in rows)
        return statistics.median(v), v[int(0.9 * (len(v) - 1))]

    print('translation step (mm): estimate median %.1f p90 %.1f | ground truth median %.1f p90 %.1f' %
          (*stat(0), *stat(1)))
    print('rotation step (deg):   estimate median %.2f p90 %.2f | ground truth median %.2f p90 %.2f' %
          (*stat(2), *stat(3)))


if __name__ == '__main__':
    main()
