"""A JupyterLab server for the notebook browser tests: started on 127.0.0.1 with a token in a
folder of its own, which is its home too (its settings, runtime files, the kernel's IPython
folder, npm's logs: none in the user's home), its kernel in this interpreter's environment,
stopped afterwards.

Tests wait on the server's REST API (jupyter_server's ``/api/sessions``: a session's kernel,
its ``execution_state`` and its ``connections``), never on the page's text, which each
JupyterLab release may word otherwise (4.6 dropped the status bar's "| Idle")."""

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
        env = {**os.environ, "HOME": str(root), "JUPYTER_CONFIG_DIR": str(root / ".jupyter-config"),
               "JUPYTER_RUNTIME_DIR": str(root / ".jupyter-runtime"),
               "JUPYTERLAB_SETTINGS_DIR": str(root / ".jupyterlab-settings"),
               "JUPYTERLAB_WORKSPACES_DIR": str(root / ".jupyterlab-workspaces"),
               "JUPYTER_DATA_DIR": str(root / ".jupyter-data"),
               "IPYTHONDIR": str(root / ".ipython")}
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

    def api(self, path: str):
        """The JSON the server's REST API answers at ``path`` (e.g. "/api/sessions")."""
        with urllib.request.urlopen(f"http://127.0.0.1:{self.port}{path}?token={self.token}",
                                    timeout=10) as r:
            return json.loads(r.read())

    def kernel(self, name: str) -> dict | None:
        """The kernel model (``execution_state``, ``connections``, ...) of the session of
        notebook ``name`` (a path under the root), or None while it has none."""
        for session in self.api("/api/sessions"):
            if session.get("path") == name and session.get("kernel"):
                return session["kernel"]
        return None

    def kernel_ready(self, name: str) -> bool:
        """Whether notebook ``name``'s kernel is started, idle and connected to a page."""
        kernel = self.kernel(name)
        return bool(kernel) and kernel.get("execution_state") == "idle" and \
            kernel.get("connections", 0) >= 1

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
