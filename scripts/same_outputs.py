#!/usr/bin/env python3
"""Runs every shipped scene and compares the outputs with those of another build, byte for byte.

A reshaping of the code must change no result: this is how it is checked.

    python3 scripts/same_outputs.py run BINARY DIR [--ranks 1 2 4]
    python3 scripts/same_outputs.py compare DIR_BEFORE DIR_AFTER

`run` writes DIR/<scene>/np<N>/ for each scene and rank count (N > 1 under mpirun). `compare`
checks that both directories hold the same files with the same bytes, except the fields that
measure the machine rather than the run: in summary.json the seconds, and the manifest's times,
commit, host and command line. It exits 1 listing what differs.
"""

import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
# Keys whose values are the machine's, not the run's.
VOLATILE = ("seconds", "started", "finished", "commit", "host", "command", "version", "pid",
            "directory", "out", "files", "scene")


def scrub(value):
    if isinstance(value, dict):
        return {k: ("*" if any(v in k for v in VOLATILE) else scrub(x)) for k, x in value.items()}
    if isinstance(value, list):
        return [scrub(x) for x in value]
    return value


def run(binary, out, ranks):
    out = pathlib.Path(out)
    for scene in sorted((ROOT / "scenes").glob("*.json")):
        for n in ranks:
            target = out / scene.stem / f"np{n}"
            if target.exists():
                shutil.rmtree(target)
            command = [binary, "run", str(scene), "--out", str(target), "--json"]
            if n > 1:
                command = ["mpirun", "-np", str(n), "--oversubscribe"] + command
            env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
            result = subprocess.run(command, capture_output=True, text=True, env=env)
            print(f"{scene.stem} np{n}: exit {result.returncode}", flush=True)
            target.mkdir(parents=True, exist_ok=True)
            (target / "exit_code.txt").write_text(f"{result.returncode}\n")


def compare(before, after):
    before, after = pathlib.Path(before), pathlib.Path(after)
    names = lambda d: {p.relative_to(d) for p in d.rglob("*") if p.is_file()}
    a, b = names(before), names(after)
    differ = [f"only in {before}: {p}" for p in sorted(a - b)]
    differ += [f"only in {after}: {p}" for p in sorted(b - a)]
    for p in sorted(a & b):
        x, y = (before / p).read_bytes(), (after / p).read_bytes()
        if p.suffix == ".json" and p.name in ("summary.json", "manifest.json"):
            x, y = (json.dumps(scrub(json.loads(t)), sort_keys=True) for t in (x, y))
        if x != y:
            differ.append(f"differs: {p}")
    print("\n".join(differ) if differ else f"identical: {len(a)} files")
    return 1 if differ else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="what", required=True)
    r = sub.add_parser("run")
    r.add_argument("binary")
    r.add_argument("dir")
    r.add_argument("--ranks", type=int, nargs="+", default=[1])
    c = sub.add_parser("compare")
    c.add_argument("before")
    c.add_argument("after")
    args = parser.parse_args()
    if args.what == "run":
        run(args.binary, args.dir, args.ranks)
        return 0
    return compare(args.before, args.after)


if __name__ == "__main__":
    sys.exit(main())
