"""Every corpus case (tests/corpus/) through `baker bake`, `inspect` and `validate`: no traceback, the expected exit
code, one line naming the problem, an earlier output left untouched and no temporary file behind, no file opened
outside the case's folder (a Python audit hook in the child logs every open) and no HTTP request made."""
from __future__ import annotations

import http.server
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
from corpus.make_corpus import SECRET, all_cases, write  # noqa: E402

REPO = Path(__file__).parents[1]
EARLIER = b"an earlier output that a failed run must leave as it was"
AUDIT = '''
import os, sys
_fd = os.open(os.environ["BAKER_AUDIT_LOG"], os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o600)
def _hook(event, args):
    if event == "open" and args and isinstance(args[0], (str, bytes)):
        path = args[0].decode(errors="replace") if isinstance(args[0], bytes) else args[0]
        os.write(_fd, (os.path.abspath(path) + "\\n").encode(errors="replace"))
sys.addaudithook(_hook)
'''


class Counter(http.server.BaseHTTPRequestHandler):
    requests = 0

    def do_GET(self):  # noqa: N802 (http.server's naming)
        Counter.requests += 1
        self.send_response(200)
        self.end_headers()
        self.wfile.write(SECRET)

    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Counter)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    root = tmp_path_factory.mktemp("corpus")
    made = write(root, http=f"http://127.0.0.1:{server.server_address[1]}/")
    audit = root / "audit"
    audit.mkdir()
    (audit / "sitecustomize.py").write_text(AUDIT)
    yield root, made, audit
    server.shutdown()
    assert Counter.requests == 0, f"{Counter.requests} HTTP requests were made"


RUNS = [(case.name, command) for case in all_cases() for command in case.commands]


@pytest.mark.parametrize("name, command", RUNS, ids=[f"{n}-{c}" for n, c in RUNS])
def test_case(corpus, name, command, tmp_path):
    root, made, audit = corpus
    case, source = made[name]
    folder = source.parent
    output = folder / f"out-{command}.glb"
    outputs = [output] + [folder / f"{output.name}{suffix}" for suffix in case.side_outputs]
    for path in outputs:
        path.write_bytes(EARLIER)
    before = sorted(p.name for p in folder.iterdir())
    log = tmp_path / "opened.txt"
    argv = [a.format(input=source, output=output, http=case) for a in case.commands[command]]
    env = {**os.environ, "BAKER_AUDIT_LOG": str(log), "PYTHONPATH": os.pathsep.join([str(audit), str(REPO)])}
    requests = Counter.requests
    result = subprocess.run([sys.executable, "-m", "baker.cli", *argv], cwd=folder, env=env, capture_output=True,
                            text=True, timeout=300)
    expect = case.expect[command]
    shown = f"{case.rule}\nstdout: {result.stdout[-2000:]}\nstderr: {result.stderr[-2000:]}"
    assert "Traceback" not in result.stderr, shown
    assert result.returncode == expect.exit, shown
    if expect.exit == 2:
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("baker: error: "), shown
        for word in expect.words:
            assert word in lines[0], shown
    elif command == "validate":
        for word in expect.words:
            assert word in result.stdout, shown
    if result.returncode != 0 or command != "bake":
        for path in outputs:
            assert path.read_bytes() == EARLIER, f"a failed or read-only run changed an earlier output: {path.name}"
    after = sorted(p.name for p in folder.iterdir())
    assert after == before, f"files left behind: {sorted(set(after) - set(before))}"
    assert Counter.requests == requests, "baker made an HTTP request"
    outside = [line for line in log.read_text().splitlines() if Path(line).is_relative_to(root)
               and not Path(line).is_relative_to(folder) and not Path(line).is_relative_to(audit)]
    assert not outside, f"opened outside the asset's folder: {outside}"
    for path in outputs:
        path.unlink()
