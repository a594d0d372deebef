#!/usr/bin/env python3
"""ATE of a generated scenario over several seeds, with and without GMC, next to standing still.

One seed of a crowd scenario is an anecdote as much as one real window is: the same
code can be 0.02 m off on one seed and 0.10 m on the next. For each seed this generates
config/sim/<scenario>.ini (kept in --data, reused when already there), runs
gmc-rgbd-mapping (no map) with GMC and with GMC off, and gmc-eval; "standing still" is
the ATE of a camera that never moves over the same frames (scripts/window_eval.py).
Prints a Markdown table, then the median and max with GMC.

  scripts/seed_eval.py stop_and_go 1 2 3 4 5 6 [--bin build/bin] [--frames 300]
      [--set Section.key=value ...]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from window_eval import standing_still_ate  # noqa: E402


def generate(args, seed):
    folder = os.path.join(args.data, '%s_seed%d_%d' % (args.scenario, seed, args.frames))
    if not os.path.exists(os.path.join(folder, 'groundtruth.txt')):
        subprocess.run([os.path.join(args.bin, 'gmc-sim'), 'config/sim/%s.ini' % args.scenario, '--out', folder,
                        '--seed', str(seed), '--frames', str(args.frames)], check=True, stdout=subprocess.DEVNULL)
    return folder


def run(args, folder, extra):
    with tempfile.TemporaryDirectory() as out:
        cmd = [os.path.join(args.bin, 'gmc-rgbd-mapping'), args.config, folder, '--out', out,
               '--set', 'Output.map=false', '--set', 'Playback.progress=false']
        for s in args.set + extra:
            cmd += ['--set', s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        est, gt, js = os.path.join(out, 'trajectory_tum.txt'), os.path.join(folder, 'groundtruth.txt'), \
            os.path.join(out, 'eval.json')
        subprocess.run([os.path.join(args.bin, 'gmc-eval'), '--gt', gt, '--est', est, '--json', js],
                       check=True, stdout=subprocess.DEVNULL)
        with open(js) as f:
            ate = json.load(f)['ate']['rmse']
        with open(os.path.join(out, 'summary.json')) as f:
            lost = json.load(f).get('lost', 0)
        return ate, lost, standing_still_ate(est, gt)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('scenario', help='config/sim/<scenario>.ini')
    p.add_argument('seeds', nargs='+', type=int)
    p.add_argument('--bin', default='build/bin')
    p.add_argument('--config', default='config/default.ini')
    p.add_argument('--frames', type=int, default=300)
    p.add_argument('--data', default='out/seeds', help='generated sequences, reused')
    p.add_argument('--set', action='append', default=[], help='Section.key=value for every run')
    args = p.parse_args()
    print('| scenario | seed | ATE with GMC (m) | lost | without GMC (m) | standing still (m) |')
    print('|---|---|---|---|---|---|')
    with_gmc = []
    for seed in args.seeds:
        folder = generate(args, seed)
        ate, lost, still = run(args, folder, [])
        off, _, _ = run(args, folder, ['GMC.enabled=false'])
        with_gmc.append(ate)
        print('| %s | %d | %.4f | %d | %.4f | %.4f |' % (args.scenario, seed, ate, lost, off, still))
        sys.stdout.flush()
    print('\n%s: %d seeds, with GMC median %.4f m, max %.4f m' % (
        args.scenario, len(with_gmc), statistics.median(with_gmc), max(with_gmc)))


if __name__ == '__main__':
    main()
