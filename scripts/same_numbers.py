"""Runs every example with two `contactdd` binaries and compares the numbers that an output-format
change must not move: iteration counts, per-iteration relative changes, contact forces, gaps, the
points' own signed pressures (`nodal_traction`; `pressure` in builds that wrote σ_n there), load
steps, and the VTU displacement fields. `scripts/same_outputs.sh` compares whole files; this
compares the numbers where the files' layout differs on purpose.

Usage: python3 scripts/same_numbers.py REFERENCE_BINARY CURRENT_BINARY   (exit 1 on a difference)
"""
import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
ref, cur = sys.argv[1], sys.argv[2]
root = Path(tempfile.mkdtemp())
bad = 0
for ex in sorted(Path('examples').glob('*.toml')):
    outs = {}
    for name, binary in [('ref', ref), ('cur', cur)]:
        out = root / name / ex.stem
        subprocess.run([binary, 'solve', str(ex), '--out', str(out), '--quiet'], capture_output=True)
        outs[name] = out
    a = json.loads((outs['ref'] / 'summary.json').read_text())
    b = json.loads((outs['cur'] / 'summary.json').read_text())
    checks = {
        'iterations': (a['iterations'], b['iterations']),
        'rel_change': ([h['rel_change'] for h in a['history']], [h['rel_change'] for h in b['history']]),
        'force': ([c['force'] for c in a['contact']], [c['force'] for c in b['contact']]),
        'gap': ([c['gap'] for c in a['contact']], [c['gap'] for c in b['contact']]),
        'signed pressure': ([c.get('nodal_traction', c['pressure']) for c in a['contact']],
                            [c.get('nodal_traction', c['pressure']) for c in b['contact']]),
        'steps': ([(s['iterations'], s['pairs'][0]['force']) for s in a.get('steps', [])],
                  [(s['iterations'], s['pairs'][0]['force']) for s in b.get('steps', [])]),
    }
    for vtu in sorted(outs['ref'].glob('*.vtu')):
        ta, tb = vtu.read_text(), (outs['cur'] / vtu.name).read_text()
        grab = lambda t: re.search(r'Name="displacement"[^>]*>(.*?)</DataArray>', t, re.S).group(1).split()
        checks['displacement ' + vtu.stem] = (grab(ta), grab(tb))
    for key, (x, y) in checks.items():
        if x != y:
            bad += 1
            print(f'{ex.stem}: {key} differs')
    print(f'{ex.stem}: {len(checks)} quantities compared')
shutil.rmtree(root)
print('differences:', bad)
sys.exit(1 if bad else 0)
