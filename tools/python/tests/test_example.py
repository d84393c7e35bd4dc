"""The example of docs/python.md and the README runs as written (tools/python/example.py)."""

import subprocess
import sys

from conftest import SOURCE


def test_example_runs(tmp_path):
    out = tmp_path / "example.png"
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "python" / "example.py"), str(out)],
                       cwd=SOURCE, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert "crossing boxes" in p.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
