#!/usr/bin/env python3
"""ATE of a generated scenario over several seeds, with and without GMC, next to standing still.

One seed of a crowd scenario is an anecdote as much as one real window is: the same
code can be 0.02 m off on one seed and 0.10 m on the next. For each seed this generates
config/sim/<scenario>.ini (kept in --data, reused when already there), runs
gmc-rgbd-mapping (no map) with GMC and with GMC off, and gmc-eval; "standing still" is
the ATE of a camera that never moves over the same frames (scripts/window_eval.py).
"After 1 s" is the position error 30 frames in, without alignment (scripts/start_error.py):
the ATE aligns away an offset taken in a map's first second and kept ever after
(crowd_hover seed 6: ATE 0.064 m, 0.39 m off after 1 s). Prints a Markdown table, then
the median and max with GMC and how many seeds are more than 0.1 m off after 1 s.

  scripts/seed_eval.py stop_and_go 1 2 3 4 5 6 [--bin build/bin] [--frames 300]
      [--set Section.key=value ...]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from start_error import unaligned_errors  # noqa: E402
from window_eval import run_window  # noqa: E402

START_FRAMES = 30  # 1 s at 30 Hz: a map's first second, before landmarks can have static evidence
START_FAILED = 0.1  # m off after it: the start followed something that moved


def sequence_folder(data, scenario, seed, frames):
    return os.path.join(data, '%s_seed%d_%d' % (scenario, seed, frames))


def generate_sequence(bin_dir, data, scenario, seed, frames):
    """config/sim/<scenario>.ini at one seed, made into data once and reused; its folder."""
    folder = sequence_folder(data, scenario, seed, frames)
    if not os.path.exists(os.path.join(folder, 'groundtruth.txt')):
        subprocess.run([os.path.join(bin_dir, 'gmc-sim'), 'config/sim/%s.ini' % scenario, '--out', folder,
                        '--seed', str(seed), '--frames', str(frames)], check=True, stdout=subprocess.DEVNULL)
    return folder


def generate(args, seed):
    return generate_sequence(args.bin, args.data, args.scenario, seed, args.frames)


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
    print('| scenario | seed | ATE with GMC (m) | after 1 s, unaligned (m) | lost | without GMC (m) | standing still (m) |')
    print('|---|---|---|---|---|---|---|')
    with_gmc, after_start = [], []
    for seed in args.seeds:
        folder = generate(args, seed)
        with tempfile.TemporaryDirectory() as tmp:  # first frame 0, count 0: the whole sequence
            ate, still, summary = run_window(args, folder, 0, 0, tmp)
            rows = unaligned_errors(os.path.join(tmp, 'trajectory_tum.txt'), os.path.join(folder, 'groundtruth.txt'))
        start = rows[min(START_FRAMES, len(rows) - 1)][1] if rows else float('nan')
        lost = summary.get('lost', 0)
        off_args = argparse.Namespace(**{**vars(args), 'set': args.set + ['GMC.enabled=false']})
        with tempfile.TemporaryDirectory() as tmp:
            off, _, _ = run_window(off_args, folder, 0, 0, tmp)
        with_gmc.append(ate)
        after_start.append(start)
        print('| %s | %d | %.4f | %.4f | %d | %.4f | %.4f |' % (args.scenario, seed, ate, start, lost, off, still))
        sys.stdout.flush()
    print('\n%s: %d seeds, with GMC median %.4f m, max %.4f m; %d more than %.1f m off after 1 s' % (
        args.scenario, len(with_gmc), statistics.median(with_gmc), max(with_gmc),
        sum(1 for e in after_start if not e <= START_FAILED), START_FAILED))  # NaN (no pose) counts as failed


if __name__ == '__main__':
    main()
