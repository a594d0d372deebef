#!/usr/bin/env python3
"""What scripts/bench.sh reads: the bench INI (configparser) and the JSON the apps write
(json). Python 3 standard library only. One value or one line per call:

  bench_data.py ini-get FILE SECTION KEY [DEFAULT]   value, or DEFAULT (error if neither)
  bench_data.py ini-sections FILE                    sequence sections (all but [Bench])
  bench_data.py json FILE PATH [FORMAT]              value at a dotted PATH (ms.total.median)
  bench_data.py eval FILE                            "ate_rmse ate_mae rpe_t_rmse rpe_t_mae
                                                      rpe_r_rmse rpe_r_mae" from gmc-eval --json
  bench_data.py windows FILE NAME                    one Markdown row of scripts/window_eval.py's
                                                      --json for sequence NAME

A missing file, section, key or path is one line on stderr and exit code 1. JSON null (a
NaN the app could not spell) prints as "nan".
"""
import configparser
import json
import sys


def fail(message):
    print(f"bench_data: {message}", file=sys.stderr)
    sys.exit(1)


def read_ini(path):
    # ";" after whitespace starts a comment, as in MRPT (the awk reader this replaces cut
    # at any ";"; no bench value holds one);
    # keys keep their case; ${...} is left for bench.sh to expand.
    parser = configparser.ConfigParser(inline_comment_prefixes=(";",), interpolation=None,
                                       strict=True)
    parser.optionxform = str
    try:
        with open(path, encoding="utf-8") as f:
            parser.read_file(f)
    except (OSError, configparser.Error) as e:
        fail(f"{path}: {e}")
    return parser


def ini_get(path, section, key, *default):
    parser = read_ini(path)
    if parser.has_option(section, key):
        return parser.get(section, key)
    if default:
        return default[0]
    fail(f"{path}: [{section}] {key}: missing")


def ini_sections(path):
    return "\n".join(s for s in read_ini(path).sections() if s != "Bench")


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")


def json_value(path, dotted):
    value = read_json(path)
    for part in dotted.split("."):
        if not isinstance(value, dict) or part not in value:
            fail(f"{path}: no {dotted}")
        value = value[part]
    return float("nan") if value is None else value


def formatted(value, fmt=None):
    if fmt:
        return fmt % value
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def eval_line(path):
    keys = [("ate.rmse", "%.4f"), ("ate.median", "%.4f"), ("rpe.trans_rmse", "%.4f"),
            ("rpe.trans_median", "%.4f"), ("rpe.rot_rmse", "%.3f"), ("rpe.rot_median", "%.3f")]
    return " ".join(fmt % json_value(path, key) for key, fmt in keys)


def windows_row(path, name):
    """| whole (standing still) | windows median / max | below standing still | per window |"""
    report = read_json(path)
    if len(report) != 1:
        fail(f"{path}: expected one sequence, got {len(report)}")
    r = next(iter(report.values()))
    whole, wins = r["whole"], r["windows"]
    per_window = " ".join("%d: %.3f (%.3f)" % (w["first"], w["ate"], w["still"]) for w in wins)
    return "| %s | %.4f (%.3f) | %.4f / %.3f | %d of %d | %s |" % (
        name, whole["ate"], whole["still"], r["window_median"], r["window_max"],
        r["windows_below_still"], len(wins), per_window)


def main(argv):
    commands = {
        "ini-get": (3, 4, lambda a: ini_get(*a)),
        "ini-sections": (1, 1, lambda a: ini_sections(a[0])),
        "json": (2, 3, lambda a: formatted(json_value(a[0], a[1]), *a[2:])),
        "eval": (1, 1, lambda a: eval_line(a[0])),
        "windows": (2, 2, lambda a: windows_row(a[0], a[1])),
    }
    if not argv or argv[0] not in commands:
        fail("usage: bench_data.py ini-get|ini-sections|json|eval|windows ... (see the file's docstring)")
    low, high, run = commands[argv[0]]
    args = argv[1:]
    if not low <= len(args) <= high:
        fail(f"{argv[0]}: expected {low}-{high} arguments, got {len(args)}")
    print(run(args))


if __name__ == "__main__":
    main(sys.argv[1:])
