"""`kinetix studio`: bad arguments are one line; the server prints its URL with the token, answers it, and stops
cleanly on Ctrl-C and on SIGTERM."""

from __future__ import annotations

import signal
import subprocess
import urllib.error
import urllib.request

import pytest

from helpers.cli import kinetix
from helpers.paths import REPO
from helpers.processes import KINETIX, process_env


def test_bad_arguments_are_one_line(capsys, tmp_path):
    assert "nowhere: no such folder or level file" in kinetix(capsys, "studio", tmp_path / "nowhere").error_line
    line = kinetix(capsys, "studio", tmp_path, "--warm", "xl", "--no-browser").error_line
    assert "--warm: expected sizes among s, m, l" in line
    line = kinetix(capsys, "studio", tmp_path, "--allow-host", "http://me.example/", "--no-browser").error_line
    assert "--allow-host: expected a host name" in line


@pytest.mark.slow
@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM])
def test_the_server_prints_its_url_and_stops_cleanly(stop):
    args = [*KINETIX, "studio", str(REPO / "levels" / "s"), "--no-browser", "--port", "0", "--warm", ""]
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=process_env())
    try:
        lines = []
        while not any(line.startswith("open http://127.0.0.1:") for line in lines):
            lines.append(process.stdout.readline())
            assert lines[-1], "".join(lines)
        url = lines[-1].split()[1]
        assert "token=" in url
        with urllib.request.urlopen(url, timeout=30) as page:
            assert page.status == 200 and b"kinetix studio" in page.read()
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(url.split("?")[0] + "api/files", timeout=30)
        assert refused.value.code == 403
        rebound = urllib.request.Request(url, headers={"Host": "evil.example"})  # a DNS-rebinding page's request
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(rebound, timeout=30)
        assert refused.value.code == 403
        process.send_signal(stop)
        out = process.communicate(timeout=60)[0]
    finally:
        process.kill()
    assert process.returncode == 0 and "studio stopped" in out and "Traceback" not in out
