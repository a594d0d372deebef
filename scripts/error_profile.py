#!/usr/bin/env python3
"""Where a run's ATE lives: direction, frequency, and the refinement's residuals.

For one run directory of gmc-rgbd-mapping (trajectory_tum.txt, and tracking.csv when run
with Output.tracking_log=true) against a TUM ground truth:
- ATE (rigid alignment, Horn's quaternion method, stamps within 0.02 s);
- the same after smoothing the estimate over 9 and 31 frames (moving average): if the
  ATE barely drops, the error is slow drift or offset, not frame-to-frame noise (for a
  hovering camera like Bonn's; a fast camera's own path bends under the average);
- the RMS of the aligned error along the estimated camera's own axes (x right, y down,
  z forward): lateral errors are the translation-rotation trade of distant texture;
- the median over tracked frames of the refinement's median reprojection error (px)
  and depth error (m), to set against [Refinement] pixel_sigma and the depth noise model;
- of the landmarks that held one tracked frame's pose, the share the next frame matched
  again (the rest are re-found later or replaced at the next keyframe), and the
  keyframes taken per 100 frames.

  ./build/bin/gmc-rgbd-mapping config/bonn.ini $D/bonn_crowd_301_460 --out /tmp/r \\
      --set Output.map=false --set Output.tracking_log=true
  ./build/bin/gmc-eval --gt $D/bonn_crowd_301_460/groundtruth.txt --est /tmp/r/trajectory_tum.txt \\
      --gt-frame bonn --gt-out /tmp/r/groundtruth_camera.txt
  python3 scripts/error_profile.py /tmp/r /tmp/r/groundtruth_camera.txt [--frames]

Bonn's groundtruth.txt is the marker body's; gmc-eval writes the camera's (TUM's is the
camera's already).

With --frames it first prints one line per pose (with tracking.csv): the tracking state,
keyframe, matches (static / dynamic / refinement inliers), landmarks with static evidence
matched / agreeing, the refinement's position standard deviation, the aligned error and
the estimated step next to the true one (both after the alignment), and why a frame was
lost. It is where the twenty-fourth round saw a hovering camera's estimate step 10-25 mm
a frame where the camera steps 1-4 mm (doc/odometry.md).
"""
import argparse
import csv
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from window_eval import associate_pairs, read_tum  # noqa: E402


def rotation(q):
    x, y, z, w = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def largest_eigenvector(M):
    """Of a symmetric matrix, by cyclic Jacobi rotations (exact to rounding for 4x4)."""
    n = len(M)
    A = [row[:] for row in M]
    V = [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]
    for _ in range(100):
        off = sum(A[i][j] ** 2 for i in range(n) for j in range(n) if i != j)
        if off < 1e-30:
            break
        for p in range(n):
            for q in range(p + 1, n):
                if abs(A[p][q]) < 1e-300:
                    continue
                theta = (A[q][q] - A[p][p]) / (2 * A[p][q])
                t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1))
                c = 1 / math.sqrt(t * t + 1)
                s = t * c
                for k in range(n):  # A <- A J (columns p, q)
                    akp, akq = A[k][p], A[k][q]
                    A[k][p], A[k][q] = c * akp - s * akq, s * akp + c * akq
                for k in range(n):  # A <- J^T A (rows p, q)
                    apk, aqk = A[p][k], A[q][k]
                    A[p][k], A[q][k] = c * apk - s * aqk, s * apk + c * aqk
                for k in range(n):
                    vkp, vkq = V[k][p], V[k][q]
                    V[k][p], V[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    best = max(range(n), key=lambda i: A[i][i])
    return [V[k][best] for k in range(n)]


def align(P, Q):
    """Errors R*(P - mean P) + mean Q - Q of the best rotation R (Horn 1987)."""
    n = len(P)
    mp = [sum(p[i] for p in P) / n for i in range(3)]
    mq = [sum(q[i] for q in Q) / n for i in range(3)]
    A = [[p[i] - mp[i] for i in range(3)] for p in P]
    B = [[q[i] - mq[i] for i in range(3)] for q in Q]
    S = [[sum(a[i] * b[j] for a, b in zip(A, B)) for j in range(3)] for i in range(3)]
    (xx, xy, xz), (yx, yy, yz), (zx, zy, zz) = S
    N = [[xx + yy + zz, yz - zy, zx - xz, xy - yx], [yz - zy, xx - yy - zz, xy + yx, zx + xz],
         [zx - xz, xy + yx, -xx + yy - zz, yz + zy], [xy - yx, zx + xz, yz + zy, -xx - yy + zz]]
    v = largest_eigenvector(N)
    R = rotation([v[1], v[2], v[3], v[0]])
    return [[sum(R[i][j] * a[j] for j in range(3)) - b[i] for i in range(3)] for a, b in zip(A, B)], R


def rms(errors):
    return math.sqrt(sum(sum(x * x for x in e) for e in errors) / len(errors))


def smoothed(P, width):
    out = []
    for i in range(len(P)):
        lo, hi = max(0, i - width // 2), min(len(P), i + width // 2 + 1)
        out.append([sum(P[j][k] for j in range(lo, hi)) / (hi - lo) for k in range(3)])
    return out


def read_tracking(run):
    """tracking.csv's rows (empty without it)."""
    log = os.path.join(run, 'tracking.csv')
    if not os.path.exists(log):
        return []
    with open(log) as f:
        return list(csv.DictReader(f))


def frame_lines(stamps, errors, Q, every):
    """One line per pose (estimated stamps, aligned errors, ground-truth positions):
    tracking.csv's row of that stamp next to the aligned error and both steps."""
    by_stamp = {round(float(r['stamp']), 6): r for r in every}
    lines = ['frame state      kf matches static dynamic inliers evidence  sigma_mm error_cm'
             ' step_mm true_mm  lost_reason']
    previous = None
    for stamp, e, q in zip(stamps, errors, Q):
        aligned = [e[a] + q[a] for a in range(3)]
        step = math.dist(aligned, previous[0]) * 1000 if previous else 0.0
        true_step = math.dist(q, previous[1]) * 1000 if previous else 0.0
        previous = (aligned, q)
        r = by_stamp.get(round(stamp, 6), {})
        evidence = '%s/%s' % (r.get('static_landmarks_matched', '-'), r.get('static_landmarks_agreeing', '-'))
        lines.append('%5s %-10s %2s %7s %6s %7s %7s %8s %9.1f %8.1f %7.1f %7.1f  %s' % (
            r.get('frame', '-'), r.get('state', '-')[:10], r.get('keyframe', '-'), r.get('matches', '-'),
            r.get('static', '-'), r.get('dynamic', '-'), r.get('inliers', '-'), evidence,
            float(r.get('position_sigma') or 0) * 1000, math.hypot(*e) * 100, step, true_step,
            r.get('lost_reason', '')))
    return lines


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('run', help='output folder of gmc-rgbd-mapping')
    p.add_argument('groundtruth', help='TUM ground truth of the same frames')
    p.add_argument('--frames', action='store_true', help='one line per pose first')
    args = p.parse_args()
    run, gt_path = args.run, args.groundtruth
    est, gt = read_tum(os.path.join(run, 'trajectory_tum.txt')), read_tum(gt_path)
    pairs = associate_pairs([r[0] for r in est], gt)
    P = [est[i][1:4] for i, _ in pairs]
    Q = [g[1:4] for _, g in pairs]
    Rcam = [rotation(est[i][4:8]) for i, _ in pairs]
    if len(P) < 3:
        sys.exit('error_profile.py: fewer than 3 poses of %s match the ground truth' % run)
    errors, R = align(P, Q)
    every = read_tracking(run)
    if args.frames:
        print('\n'.join(frame_lines([est[i][0] for i, _ in pairs], errors, Q, every)))
    print('ATE %.4f m over %d poses; smoothed over 9 frames %.4f, over 31 frames %.4f' % (
        rms(errors), len(P), rms(align(smoothed(P, 9), Q)[0]), rms(align(smoothed(P, 31), Q)[0])))
    # Error in the estimate's world frame (R^T e), then along its camera axes (Rcam^T).
    axes = [0.0, 0.0, 0.0]
    for e, Rc in zip(errors, Rcam):
        e_world = [sum(R[k][i] * e[k] for k in range(3)) for i in range(3)]
        for i in range(3):
            axes[i] += sum(Rc[k][i] * e_world[k] for k in range(3)) ** 2
    print('error along the camera axes (RMS, m): x right %.4f, y down %.4f, z forward %.4f' % tuple(
        math.sqrt(a / len(P)) for a in axes))
    if every:
        rows = [r for r in every if r['state'] == 'tracking']
        if rows:
            print('refinement, median over %d tracked frames: reprojection %.2f px, depth %.4f m' % (
                len(rows), statistics.median(float(r['pixel_error_median']) for r in rows),
                statistics.median(float(r['depth_error_median']) for r in rows)))
        to_refind = sum(int(r['landmarks_to_refind']) for r in every)
        refound = sum(int(r['landmarks_refound']) for r in every)
        keyframes = sum(int(r['keyframe']) for r in every)
        if to_refind:
            print('landmarks that held a pose, matched again the next frame: %.1f %% (%d of %d); '
                  '%.1f keyframes per 100 frames' % (100.0 * refound / to_refind, refound, to_refind,
                                                     100.0 * keyframes / len(every)))

if __name__ == '__main__':
    main()
