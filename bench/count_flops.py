#!/usr/bin/python3
"""Floating-point operations per particle-step of each `dgmpm bench --json` case, counted from the
instructions its steps execute (this machine has no hardware counters to read).

callgrind (valgrind) counts every instruction `dgmpm bench --count-steps CASE` executes inside the
steps alone (--toggle-collect of the function that takes them), objdump names each instruction,
and each arithmetic one counts its operations: one per scalar add, subtract, multiply, divide or
square root, two per fused multiply-add, times the lanes of a packed one (two doubles in an xmm
register, four in a ymm). Comparisons, min and max, sign masks (xor, and), conversions and moves
are not flops. Instructions executed outside the binary (libm's pow, libgomp) are reported as a
share of all, not counted.

    bench/count_flops.py build/bin/dgmpm > flops.json
    build/bin/dgmpm bench --json --flop-counts flops.json

Each case is counted twice, over 2 steps and over 2 + S, and the difference divided by S steps:
what the first steps do once drops out. Options: --particles N (default 40000: the boundary
cells' share is a few per cent in 2D, as at 1e6), --steps S (default 2), --cases NAME ...
(default all). Exits non-zero, saying why, when
valgrind or objdump is missing or a count cannot be made."""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

SCALAR = re.compile(r"^v?(add|sub|mul|div|sqrt)s[sd]$")
PACKED = re.compile(r"^v?(add|sub|mul|div|sqrt|addsub|hadd|hsub)p([sd])$")
FUSED = re.compile(r"^vf(n?m(add|sub)|maddsub|msubadd)(132|213|231)([sp])([sd])$")


def flops_of(mnemonic, operands):
    """Flops one execution of the instruction performs (0 for anything but arithmetic)."""
    width = 512 if "%zmm" in operands else 256 if "%ymm" in operands else 128
    if SCALAR.match(mnemonic):
        return 1
    packed = PACKED.match(mnemonic)
    if packed:
        return width // (64 if packed.group(2) == "d" else 32)
    fused = FUSED.match(mnemonic)
    if fused:
        lanes = 1 if fused.group(4) == "s" else width // (64 if fused.group(5) == "d" else 32)
        return 2 * lanes
    return 0


def is_packed(mnemonic):
    fused = FUSED.match(mnemonic)
    return bool(PACKED.match(mnemonic)) or bool(fused and fused.group(4) == "p")


def disassemble(binary):
    """Instruction address -> (mnemonic, operands) of the binary's code."""
    out = subprocess.run(["objdump", "-d", "--no-show-raw-insn", binary], check=True,
                         capture_output=True, text=True).stdout
    table = {}
    line = re.compile(r"^\s*([0-9a-f]+):\s+([a-z][a-z0-9]*)\s*(.*)$")
    for text in out.splitlines():
        m = line.match(text)
        if m:
            table[int(m.group(1), 16)] = (m.group(2), m.group(3))
    return table


def instruction_costs(path):
    """(object, address) -> instructions executed there (self cost, calls excluded), from a
    callgrind output written with --dump-instr=yes --dump-line=no --compress-strings=no
    --compress-pos=no."""
    costs = {}
    obj = None
    skip = False
    with open(path) as f:
        for text in f:
            if skip:  # the inclusive cost line after calls=
                skip = False
                continue
            if text.startswith("ob="):
                obj = text[3:].strip()
            elif text.startswith("calls="):
                skip = True
            elif text.startswith("0x"):
                address, _, count = text.partition(" ")
                key = (obj, int(address, 16))
                costs[key] = costs.get(key, 0) + int(count.split()[0] if count.strip() else 0)
    return costs


def counted(binary, table, argv, toggle, workdir):
    """Runs `binary argv` under callgrind, counting inside the functions matching `toggle` only:
    (flops, instructions, arithmetic instructions, packed ones, share of the instructions
    executed outside the binary, the run's stdout)."""
    out_file = os.path.join(workdir, "callgrind.out")
    run = subprocess.run(
        ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out_file, "--dump-instr=yes",
         "--dump-line=no", "--compress-strings=no", "--compress-pos=no",
         "--toggle-collect=" + toggle, binary] + argv, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit("count_flops: %s: valgrind failed (%d):\n%s" % (" ".join(argv), run.returncode,
                                                                  run.stderr[-2000:]))
    costs = instruction_costs(out_file)
    real = os.path.realpath(binary)
    inside = {a: n for (o, a), n in costs.items() if o and os.path.realpath(o) == real}
    total = sum(costs.values())
    if not inside:
        sys.exit("count_flops: %s: callgrind counted nothing in %s" % (" ".join(argv), binary))
    # Position-independent binaries run at an offset: the one that puts every executed address
    # on an instruction boundary of the disassembly.
    offset = next((o for o in (0, 0x108000, 0x400000, 0x4000000)
                   if all((a - o) in table for a in inside)), None)
    if offset is None:
        sys.exit("count_flops: the executed addresses do not match %s's disassembly" % binary)
    flops = arithmetic = packed = 0
    for a, n in inside.items():
        mnemonic, operands = table[a - offset]
        f = flops_of(mnemonic, operands)
        if f:
            flops += f * n
            arithmetic += n
            packed += n if is_packed(mnemonic) else 0
    return flops, total, arithmetic, packed, 1.0 - sum(inside.values()) / total, run.stdout


def count_case(binary, table, name, particles, steps, workdir):
    """Counts per particle-step of the case's steps: the difference between runs of 2 steps and of
    steps + 2 over `steps`: what the first counted steps do once drops out (the blow-up monitor's
    energy pass, once per 16 steps, is left out unless the runs reach it)."""
    runs = []
    for n in (2, steps + 2):
        runs.append(counted(binary, table, ["bench", "--count-steps", name, "--particles",
                                            str(particles), "--steps", str(n), "--threads", "1"],
                            "*counted_steps*", workdir))
    info = json.loads(runs[0][5].strip().splitlines()[-1])
    particle_steps = info["particles"] * steps
    flops, total, arithmetic, packed = (runs[1][k] - runs[0][k] for k in range(4))
    return {
        "flops_per_particle_step": flops / particle_steps,
        "instructions_per_particle_step": total / particle_steps,
        "arithmetic_instructions_per_particle_step": arithmetic / particle_steps,
        "packed_share_of_arithmetic": packed / arithmetic if arithmetic else 0.0,
        "share_outside_binary": runs[1][4],
        "particles": info["particles"],
        "steps": steps,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("binary")
    parser.add_argument("--particles", type=int, default=40000)
    parser.add_argument("--steps", type=int, default=2)
    parser.add_argument("--cases", nargs="*")
    args = parser.parse_args()
    for tool in ("valgrind", "objdump"):
        if not shutil.which(tool):
            sys.exit("count_flops: %s is needed (Debian: apt-get install %s)"
                     % (tool, "valgrind" if tool == "valgrind" else "binutils"))
    names = args.cases or subprocess.run([args.binary, "bench", "--cases"], check=True,
                                         capture_output=True, text=True).stdout.splitlines()
    table = disassemble(args.binary)
    counts = {}
    with tempfile.TemporaryDirectory() as workdir:
        for name in names:
            counts[name] = count_case(args.binary, table, name, args.particles, args.steps,
                                      workdir)
            print("%s: %.1f flops per particle-step" % (name,
                                                        counts[name]["flops_per_particle_step"]),
                  file=sys.stderr)
    version = subprocess.run([args.binary, "--version"], capture_output=True,
                             text=True).stdout.strip()
    json.dump({"binary": version, "how": "callgrind --toggle-collect=*counted_steps*, "
               "instructions classified from objdump (bench/count_flops.py)",
               "cases": counts}, sys.stdout, indent=2)
    print()


if __name__ == "__main__":
    main()
