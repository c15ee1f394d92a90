"""The shader lab against real Shadertoy shaders: ../shared/shadertoy's runner renders its
182 shaders through `facet shader` and fails when one that ran before (its baseline.txt)
no longer does (a traceback, an error, a flat frame, a minute's timeout). Skipped, with the
reason, where the shared folder is absent."""

import subprocess
import sys

import pytest

from conftest import ROOT, SHARED_NOTE

CORPUS = ROOT.parent / "shared" / "shadertoy"


@pytest.mark.slow
def test_every_baseline_shader_still_runs(tmp_path):
    if not (CORPUS / "run.py").is_file():
        pytest.skip(f"the Shadertoy corpus is not at {CORPUS}: {SHARED_NOTE}")
    facet = tmp_path / "facet"
    facet.write_text(f"#!{sys.executable}\nimport sys\nsys.path.insert(0, {str(ROOT / 'app')!r})"
                     "\nfrom facet.cli import main\nsys.exit(main())\n")
    facet.chmod(0o755)
    run = subprocess.run([sys.executable, str(CORPUS / "run.py"), str(facet)],
                         capture_output=True, text=True, timeout=1500)
    summary = run.stdout.strip().splitlines()
    assert run.returncode == 0, "\n".join(line for line in summary if "REGRESSION" in line
                                          or "corpus" in line)
    assert summary and "; 0 of the baseline's " in summary[-1], summary[-1:]
