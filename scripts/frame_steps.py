#!/usr/bin/env python3
"""Per-frame step of an estimated trajectory next to the ground truth's.

Median and p90 of |t_i - t_(i-1)| (mm) and of the rotation angle between consecutive
poses (deg), for the estimate and for the ground truth at the same stamps (nearest
within 0.02 s). A step far larger than the ground truth's is per-frame noise; the
figures of doc/odometry.md ("Per-frame translation noise") come from:

  ./build/bin/gmc-rgbd-mapping config/bonn.ini $D/bonn_crowd_240_389 --out /tmp/s \
      --set Output.map=false --set Dataset.max_frames=70
  python3 scripts/frame_steps.py /tmp/s/trajectory_tum.txt $D/bonn_crowd_240_389/groundtruth.txt --gt-frame bonn

It also prints the per-frame step error: |estimated step - true step|, both in their own
camera frame (so it needs the camera's orientation: with --gt-frame bonn, gmc-eval
converts Bonn's marker poses and hands them over with --gt-out), its median by thirds of the true rotation rate
and its correlation with it (a rolling shutter's error would grow with the rate;
doc/odometry.md, tenth round).
"""
import argparse
import bisect
import math
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from error_profile import rotation  # noqa: E402
from window_eval import read_tum  # noqa: E402


def camera_ground_truth(args):
    """The ground truth as camera poses: Bonn's marker poses converted by gmc-eval itself
    (--gt-out), so the conversion lives in one place (gmc::datasets::bonnBodyToCamera)."""
    if args.gt_frame == 'camera':
        return read_tum(args.gt)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'gt.txt')
        subprocess.run([os.path.join(args.bin, 'gmc-eval'), '--gt', args.gt, '--gt-frame', args.gt_frame,
                        '--est', args.est, '--gt-out', out], check=True, stdout=subprocess.DEVNULL)
        return read_tum(out)


def camera_step(a, b):
    """b's position in a's camera frame (m)."""
    m = rotation(a[4:8])
    d = [b[k] - a[k] for k in (1, 2, 3)]
    return [sum(m[j][i] * d[j] for j in range(3)) for i in range(3)]


def angle_deg(q1, q2):
    return 2 * math.degrees(math.acos(min(1.0, abs(sum(a * b for a, b in zip(q1, q2))))))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('est', help='estimated trajectory (TUM format)')
    p.add_argument('gt', help='ground truth (TUM format)')
    p.add_argument('--gt-frame', choices=('camera', 'bonn'), default='camera', help="as gmc-eval's --gt-frame")
    p.add_argument('--bin', default='build/bin', help='where gmc-eval is (for --gt-frame bonn)')
    args = p.parse_args()
    est, gt = read_tum(args.est), camera_ground_truth(args)
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
                         angle_deg(a[4:8], b[4:8]), angle_deg(ga[4:8], gb[4:8]),
                         1000 * math.dist(camera_step(a, b), camera_step(ga, gb))))
    if not rows:
        sys.exit('frame_steps.py: no consecutive estimated poses with ground truth within 0.02 s')

    def stat(k):
        v = sorted(r[k] for r in rows)
        return statistics.median(v), v[int(0.9 * (len(v) - 1))]

    print('translation step (mm): estimate median %.1f p90 %.1f | ground truth median %.1f p90 %.1f' %
          (*stat(0), *stat(1)))
    print('rotation step (deg):   estimate median %.2f p90 %.2f | ground truth median %.2f p90 %.2f' %
          (*stat(2), *stat(3)))
    by_rate = sorted(rows, key=lambda r: r[3])
    n = len(by_rate)
    thirds = [statistics.median(r[4] for r in by_rate[k * n // 3:(k + 1) * n // 3] or [(0, 0, 0, 0, 0)])
              for k in range(3)]
    err, rate = [r[4] for r in rows], [r[3] for r in rows]
    me, mr = statistics.mean(err), statistics.mean(rate)
    den = math.sqrt(sum((e - me) ** 2 for e in err) * sum((r - mr) ** 2 for r in rate))
    corr = sum((e - me) * (r - mr) for e, r in zip(err, rate)) / den if den > 0 else float('nan')
    print('step error (mm, camera frame): median %.1f p90 %.1f | by thirds of the rotation rate %.1f / %.1f / %.1f, '
          'correlation with it %.2f' % (*stat(4), *thirds, corr))


if __name__ == '__main__':
    main()
