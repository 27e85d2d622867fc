#!/usr/bin/env python3
"""make_coq.py -- Coq certificates of the Gappa proofs (stretch; CMake target proofs_coq).

For each proofs/NAME.g: run gappa (the `?` goals give the certified enclosures), write NAME_inst.g
with those enclosures as explicit goals, let `gappa -Bcoq` emit the proof script, turn each
rewriting hint (which Gappa's back end leaves as a `Hypothesis` equality) into a `Lemma` proved
by `ring` (they are field identities; a hint that is not one makes coqc fail), and check the
script with coqc against Gappa's Coq library (Debian: coq, libcoq-gappa, libcoq-flocq).
Exit 0 when every script is accepted by Coq.
Usage: make_coq.py [--root DIR] [--out DIR]
"""
import glob
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import importlib.machinery  # noqa: E402
import importlib.util  # noqa: E402

loader = importlib.machinery.SourceFileLoader("gcheck", os.path.join(os.path.dirname(HERE), "check"))
spec = importlib.util.spec_from_loader("gcheck", loader)
gcheck = importlib.util.module_from_spec(spec)
loader.exec_module(gcheck)


def gappa_num(f):
    """A Fraction with a power-of-two denominator in Gappa's m b e syntax."""
    n, d = f.numerator, f.denominator
    e = d.bit_length() - 1
    assert d == 1 << e, "enclosure bound is not dyadic"
    return f"{n}b-{e}" if e else f"{n}"


def main():
    args = sys.argv[1:]
    root = args[args.index("--root") + 1] if "--root" in args else os.path.dirname(os.path.dirname(HERE))
    out = args[args.index("--out") + 1] if "--out" in args else os.path.join(root, "build", "proofs", "coq")
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    bad = 0
    for g in sorted(glob.glob(os.path.join(root, "proofs", "*.g"))):
        name = os.path.basename(g)[:-2]
        text = open(g).read()
        res = gcheck.run_gappa(text)
        if isinstance(res, str):
            print(f"{name}: {res}")
            bad += 1
            continue
        for goal, (lo, hi) in res.items():
            text = text.replace(f"{goal} in ?", f"{goal} in [{gappa_num(lo)}, {gappa_num(hi)}]")
        inst = os.path.join(out, f"{name}_inst.g")
        open(inst, "w").write(text)
        p = subprocess.run(["gappa", "-Bcoq", inst], capture_output=True, text=True)
        if p.returncode != 0:
            print(f"{name}: gappa -Bcoq failed:\n{p.stderr[-2000:]}")
            bad += 1
            continue
        v = re.sub(r"^Hypothesis (a\d+) : (.*)\.$", r"Lemma \1 : \2.\nProof. ring. Qed.",
                   p.stdout, flags=re.M)
        v = "From Coq Require Import Reals.\nOpen Scope R_scope.\n" + v
        vfile = os.path.join(out, f"gappa_{name}.v")
        open(vfile, "w").write(v)
        c = subprocess.run(["coqc", os.path.basename(vfile)], capture_output=True, text=True, cwd=out)
        ok = c.returncode == 0 and "Hypothesis" not in v and "Admitted" not in v
        print(f"{name}: Coq {'accepts' if ok else 'REJECTS'} {vfile}")
        if not ok:
            print(c.stdout[-2000:], c.stderr[-2000:])
            bad += 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
