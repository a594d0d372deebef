#!/usr/bin/env python3
"""ATE over many windows and start offsets of real sequences, next to standing still.

For each sequence: the whole folder, then windows of --window frames starting every
--step frames. Each window runs gmc-rgbd-mapping (no map) and gmc-eval; the
"standing still" figure of the same frames is the RMS of the ground-truth positions
(associated to the estimate's stamps within 0.02 s) about their mean, i.e. the ATE of a
camera that never moves. Prints a Markdown table and the median and max per sequence.

With --random-seeds N every run is repeated with [Odometry] random_seed = 0 .. N-1
(other, equally valid RANSAC sampling streams) and each window's figure is the median
over them, its spread (min-max) in its own column: a single run's ATE on crowded frames
moves by tens of percent with the sampling alone (doc/odometry.md, twenty-first round).

  scripts/window_eval.py --bin build/bin --config config/bonn.ini \
      ../shared/data/bonn_crowd_240_389 ../shared/data/bonn_crowd_301_460
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor


def read_tum(path):
    rows = []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts or parts[0].startswith('#'):
                continue
            rows.append([float(v) for v in parts[:8]])
    return rows


def associate_pairs(est_stamps, gt, max_dt=0.02):
    """(index into est_stamps, nearest ground-truth row) for every stamp with one within max_dt."""
    gt_stamps = [r[0] for r in gt]
    out = []
    j = 0
    for i, s in enumerate(est_stamps):
        while j + 1 < len(gt_stamps) and abs(gt_stamps[j + 1] - s) <= abs(gt_stamps[j] - s):
            j += 1
        if abs(gt_stamps[j] - s) <= max_dt:
            out.append((i, gt[j]))
    return out


def associate(est_stamps, gt, max_dt=0.02):
    """Nearest ground-truth row per estimated stamp, each within max_dt."""
    return [row for _, row in associate_pairs(est_stamps, gt, max_dt)]


def standing_still_ate(est_path, gt_path):
    est = read_tum(est_path)
    gt = associate([r[0] for r in est], read_tum(gt_path))
    if not gt:
        return float('nan')
    mean = [sum(r[k] for r in gt) / len(gt) for k in (1, 2, 3)]
    return math.sqrt(sum(sum((r[k] - mean[k - 1]) ** 2 for k in (1, 2, 3)) for r in gt) / len(gt))


def run_window(args, folder, first, count, out_dir, random_seed=0):
    cmd = [os.path.join(args.bin, 'gmc-rgbd-mapping'), args.config, folder, '--out', out_dir,
           '--set', 'Output.map=false', '--set', 'Playback.progress=false',
           '--set', 'Dataset.first_frame=%d' % first, '--set', 'Dataset.max_frames=%d' % count]
    for s in args.set:
        cmd += ['--set', s]
    if random_seed:
        cmd += ['--set', 'Odometry.random_seed=%d' % random_seed]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    est = os.path.join(out_dir, 'trajectory_tum.txt')
    gt = os.path.join(folder, 'groundtruth.txt')
    js = os.path.join(out_dir, 'eval.json')
    subprocess.run([os.path.join(args.bin, 'gmc-eval'), '--gt', gt, '--est', est, '--json', js],
                   check=True, stdout=subprocess.DEVNULL)
    with open(js) as f:
        ate = json.load(f)['ate']['rmse']
    with open(os.path.join(out_dir, 'summary.json')) as f:
        summary = json.load(f)
    return ate, standing_still_ate(est, gt), summary


def run_seeds(args, folder, first, count):
    """(median ATE, every seed's ATE, standing still, lost of the median run) over the seeds."""
    def one(seed):
        with tempfile.TemporaryDirectory() as tmp:
            ate, still, summary = run_window(args, folder, first, count, tmp, seed)
        return ate, still, summary.get('lost', 0)
    with ThreadPoolExecutor(args.jobs) as pool:
        runs = list(pool.map(one, range(args.random_seeds)))
    ates = [r[0] for r in runs]
    lost = sorted(runs)[len(runs) // 2][2]
    return statistics.median(ates), ates, runs[0][1], lost


def frames_in(folder):
    with open(os.path.join(folder, 'rgb.txt')) as f:
        return sum(1 for line in f if line.strip() and not line.startswith('#'))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('folders', nargs='+')
    p.add_argument('--bin', default='build/bin')
    p.add_argument('--config', default='config/bonn.ini')
    p.add_argument('--window', type=int, default=100)
    p.add_argument('--step', type=int, default=10)
    p.add_argument('--set', action='append', default=[], help='Section.key=value for every run')
    p.add_argument('--json', help='write every figure here')
    p.add_argument('--random-seeds', type=int, default=1,
                   help='runs per window, [Odometry] random_seed 0..N-1; the figure is their median')
    p.add_argument('--jobs', type=int, default=1, help='runs at once (one per core)')
    args = p.parse_args()
    if args.random_seeds < 1 or args.jobs < 1:
        sys.exit('window_eval.py: --random-seeds and --jobs must be at least 1')
    report = {}
    print('| sequence | first frame | frames | ATE (m) | over seeds (min-max) | standing still (m) | lost | below still |')
    print('|---|---|---|---|---|---|---|---|')
    for folder in args.folders:
        name = os.path.basename(os.path.normpath(folder))
        n = frames_in(folder)
        windows = [(0, 0)] + [(s, args.window) for s in range(0, n - args.window + 1, args.step)]
        rows = []
        for first, count in windows:
            ate, per_seed, still, lost = run_seeds(args, folder, first, count)
            rows.append({'first': first, 'frames': count or n, 'ate': ate, 'ate_per_seed': per_seed,
                         'still': still, 'lost': lost})
            spread = '%.4f-%.4f' % (min(per_seed), max(per_seed)) if args.random_seeds > 1 else '-'
            print('| %s | %d | %s | %.4f | %s | %.4f | %s | %s |' % (
                name, first, count or 'all', ate, spread, still, lost, 'yes' if ate < still else 'NO'))
            sys.stdout.flush()
        win = [r['ate'] for r in rows[1:]]
        report[name] = {'whole': rows[0], 'windows': rows[1:],
                        'window_median': statistics.median(win), 'window_max': max(win),
                        'windows_below_still': sum(1 for r in rows[1:] if r['ate'] < r['still']),
                        'runs_below_still': sum(1 for r in rows[1:] for a in r['ate_per_seed'] if a < r['still']),
                        'runs': sum(len(r['ate_per_seed']) for r in rows[1:])}
    print()
    for name, r in report.items():
        print('%s: whole %.4f m; %d windows: median %.4f m, max %.4f m, %d/%d below standing still' % (
            name, r['whole']['ate'], len(r['windows']), r['window_median'], r['window_max'],
            r['windows_below_still'], len(r['windows'])), end='')
        print('; single runs: %d/%d below' % (r['runs_below_still'], r['runs']) if args.random_seeds > 1 else '')
    if args.json:
        with open(args.json, 'w') as f:
            json.dump(report, f, indent=1)


if __name__ == '__main__':
    main()
