"""A JupyterLab server for the notebook browser test: started on 127.0.0.1 with a token in a
folder of its own, its kernel in this interpreter's environment, stopped afterwards."""

from __future__ import annotations

import json
import os
import secrets
import signal
import socket
import subprocess
import sys
import urllib.request
from pathlib import Path

from browser import wait_for


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def notebook(path: Path, cells: list[str]) -> None:
    """Write a notebook of code cells."""
    nb = {"cells": [{"cell_type": "code", "execution_count": None, "metadata": {},
                     "outputs": [], "source": src} for src in cells],
          "metadata": {"kernelspec": {"name": "python3", "display_name": "Python 3",
                                      "language": "python"}},
          "nbformat": 4, "nbformat_minor": 5}
    path.write_text(json.dumps(nb))


class JupyterLab:
    def __init__(self, root: Path):
        self.root, self.port, self.token = root, free_port(), secrets.token_hex(16)
        env = {**os.environ, "JUPYTER_CONFIG_DIR": str(root / ".jupyter-config"),
               "JUPYTER_RUNTIME_DIR": str(root / ".jupyter-runtime"),
               "JUPYTERLAB_SETTINGS_DIR": str(root / ".jupyterlab-settings"),
               "JUPYTERLAB_WORKSPACES_DIR": str(root / ".jupyterlab-workspaces")}
        self.log = open(root / "jupyter.log", "w")
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "jupyterlab", "--no-browser", "--ip=127.0.0.1",
             f"--port={self.port}", f"--IdentityProvider.token={self.token}", "--allow-root",
             f"--ServerApp.root_dir={root}", "--ServerApp.port_retries=0",
             "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
             "--LabApp.news_url=None"],
            cwd=root, env=env, stdout=self.log, stderr=subprocess.STDOUT)
        wait_for(self._answers, "JupyterLab to answer")

    def _answers(self) -> bool:
        if self.proc.poll() is not None:
            raise AssertionError("JupyterLab exited: " + (self.root / "jupyter.log").read_text())
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{self.port}/api/status?token="
                                        f"{self.token}", timeout=5) as r:
                return r.status == 200
        except OSError:
            return False

    def url(self, name: str) -> str:
        return f"http://127.0.0.1:{self.port}/lab/tree/{name}?token={self.token}"

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(10)
        self.log.close()
