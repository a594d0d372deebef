#!/usr/bin/env python3
"""One TUM-layout folder from overlapping folders of the same recording.

The shared Bonn folders are two overlapping stretches of one sequence (RGB frames
240-389 and 301-460 of rgbd_bonn_crowd). A window study over their union (221 frames)
starts maps in more places than either folder alone, and runs longer. The output holds
symbolic links to the images (nothing is copied) and the union of rgb.txt, depth.txt and
groundtruth.txt, one line per timestamp. Timestamps that appear in several folders must
name the same file; the folders must not leave a gap between them (checked on rgb.txt:
no step between consecutive stamps over 1.5 times the median step).

  scripts/join_folders.py OUT FOLDER FOLDER [...]
  scripts/window_eval.py --config config/bonn.ini OUT

OUT must not exist yet (it is written to OUT.tmp and renamed).
"""
import argparse
import os
import shutil
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from window_eval import frames_in  # noqa: E402

LISTS = ('rgb.txt', 'depth.txt', 'groundtruth.txt')


def fail(message):
    print('join_folders: %s' % message, file=sys.stderr)
    sys.exit(1)


def read_list(path):
    """(header lines, {stamp text: rest of the line, without its newline})."""
    header, rows = [], {}
    with open(path) as f:
        for line in f:
            if line.startswith('#'):
                header.append(line)
                continue
            parts = line.split(None, 1)
            if parts:
                rows[parts[0]] = parts[1].rstrip('\n') if len(parts) > 1 else ''
    return header, rows


def check_no_gap(stamps):
    """The folders must continue one another: no step over 1.5 times the median one."""
    steps = [float(b) - float(a) for a, b in zip(stamps, stamps[1:])]
    if not steps:
        return
    limit = 1.5 * statistics.median(steps)
    for a, b, step in zip(stamps, stamps[1:], steps):
        if step > limit:
            fail('the folders leave a gap in rgb.txt between stamps %s and %s' % (a, b))


def join(folders, out):
    for name in LISTS:
        header, union = None, {}
        for folder in folders:
            path = os.path.join(folder, name)
            if not os.path.exists(path):
                fail('%s: missing' % path)
            h, rows = read_list(path)
            header = header or h
            for stamp, rest in rows.items():
                if stamp in union and union[stamp].split() != rest.split():
                    fail('%s: stamp %s differs from another folder (%s vs %s)' % (
                        path, stamp, rest.strip(), union[stamp].strip()))
                union[stamp] = rest
        stamps = sorted(union, key=float)
        if name == 'rgb.txt':
            check_no_gap(stamps)
        with open(os.path.join(out, name), 'w') as f:
            f.writelines(header)
            f.writelines('%s %s\n' % (s, union[s]) for s in stamps)
    for sub in ('rgb', 'depth'):
        os.makedirs(os.path.join(out, sub))
        for folder in folders:
            for image in sorted(os.listdir(os.path.join(folder, sub))):
                link = os.path.join(out, sub, image)
                if not os.path.exists(link):
                    os.symlink(os.path.abspath(os.path.join(folder, sub, image)), link)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('out')
    p.add_argument('folders', nargs='+')
    args = p.parse_args()
    if os.path.exists(args.out):
        fail('%s: exists already' % args.out)
    tmp = args.out.rstrip('/') + '.tmp'
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    try:
        join(args.folders, tmp)
    except SystemExit:
        shutil.rmtree(tmp, ignore_errors=True)  # nothing half-written is left behind
        raise
    os.rename(tmp, args.out)
    print('%s: %d frames from %d folders' % (args.out, frames_in(args.out), len(args.folders)))


if __name__ == '__main__':
    main()
