"""The level studio's HTTP API through Starlette's test client: the token, the Host check, the per-port cookie,
path escapes, malformed and oversized requests, files that cannot be shown, checking, saving, playing a level to a
solution that `kinetix validate --play` accepts, and watching and evaluating a trained agent."""

from __future__ import annotations

import asyncio
import json
import os
import re
import shlex
import shutil

import pytest
from starlette.testclient import TestClient

from helpers.paths import REFERENCE_LEVELS, REPO
from kinetix_cli.errors import LevelError
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.solution import check_level, decode_solution
from kinetix_cli.studio import service
from kinetix_cli.studio.app import MAX_BODY, STATIC, TOKEN_HEADER, cookie_name, create_app
from kinetix_cli.studio.service import MAX_EPISODES, Studio
from kinetix_cli.studio.workspace import MAX_LEVEL_BYTES

TOKEN = "test-token"
AUTH = {TOKEN_HEADER: TOKEN}
LEVEL = "rocket-car-jump.json"
PORT = 8765
LOCAL = "http://localhost"  # the test client's address: a Host the studio answers


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """The studio's folder: one shipped level, one file that is not UTF-8, one holding a bare NaN, a hidden file,
    and a link to a file outside."""
    root = tmp_path_factory.mktemp("studio")
    shutil.copy(REPO / "levels" / "s" / LEVEL, root / LEVEL)
    (root / "latin1.json").write_bytes(b'{"name": "caf\xe9"}')
    (root / "nan.json").write_text((root / LEVEL).read_text().replace("[0.8, 0.6]", "[NaN, 0.6]", 1))
    (root / ".hidden.json").write_text((root / LEVEL).read_text())
    outside = tmp_path_factory.mktemp("outside") / "secret.json"
    outside.write_text(json.dumps({"secret": 1}))
    (root / "link.json").symlink_to(outside)
    return root


@pytest.fixture(scope="module")
def client(folder):
    return TestClient(create_app(Studio(folder), TOKEN, port=PORT), base_url=LOCAL)


@pytest.fixture(scope="module")
def level(client):
    return client.get("/api/level", params={"path": LEVEL}, headers=AUTH).json()["level"]


def test_every_request_needs_the_sessions_token(client):
    assert client.get("/api/files").status_code == 403
    assert client.get("/api/files", headers={TOKEN_HEADER: "guess"}).status_code == 403
    assert client.post("/api/check", json={"level": {}}, headers={TOKEN_HEADER: "guess"}).status_code == 403
    fresh = TestClient(client.app, base_url=LOCAL)  # no cookie yet
    assert fresh.get("/").status_code == 403 and fresh.get("/static/studio.js").status_code == 403
    page = fresh.get("/", params={"token": TOKEN})
    assert page.status_code == 200 and f'content="{TOKEN}"' in page.text
    assert fresh.get("/static/studio.js").status_code == 200  # the page's files, by the cookie the page set
    assert fresh.get("/api/files").status_code == 403  # the API wants the header, which other sites cannot send
    assert "frame-ancestors 'none'" in page.headers["content-security-policy"]


def test_the_page_is_es_modules_served_as_they_are(client):
    page = client.get("/", params={"token": TOKEN})
    assert '<script type="module" src="/static/studio.js">' in page.text
    imported = set()
    for name, media in STATIC.items():
        answer = client.get(f"/static/{name}")
        assert answer.status_code == 200 and answer.headers["content-type"].startswith(media), name
        imported |= set(re.findall(r"^import (?:.* from )?'\./([\w.]+)';$", answer.text, re.M))
    assert imported == {name for name in STATIC if name.endswith(".js")} - {"studio.js"}  # each served, each used


def test_paths_stay_inside_the_folder(client, folder, level):
    for path in ("../x.json", "/etc/passwd", "a/../../x.json", "link.json"):
        answer = client.get("/api/level", params={"path": path}, headers=AUTH)
        assert answer.status_code == 403, path
        saved = client.post("/api/save", json={"path": path, "level": level, "overwrite": True}, headers=AUTH)
        assert saved.status_code == 403 and "outside the studio's folder" in saved.json()["error"]
    assert json.loads((folder / "link.json").read_text()) == {"secret": 1}
    assert not (folder.parent / "x.json").exists()
    agent = client.post("/api/watch/start", json={"level": level, "agent": "../runs/tiny"}, headers=AUTH)
    assert agent.status_code == 403


def test_malformed_and_oversized_requests_are_4xx_and_the_server_goes_on(client, level):
    bad = [
        (b"{not json", 400, "not valid JSON"),
        (b"\xff\xfe", 400, "not UTF-8"),
        (b"[1, 2]", 400, "expected a JSON object"),
        (b"{}", 400, "level: missing"),
        (b" " * (MAX_BODY + 1), 413, "at most"),
    ]
    for body, status, message in bad:
        answer = client.post("/api/check", content=body, headers=AUTH)
        assert answer.status_code == status and message in answer.json()["error"], body[:20]
    for body in (b'{"level": NaN}', b'{"level": {"gravity": [0, -Infinity]}}', b'{"level": 1e999}'):
        answer = client.post("/api/check", content=body, headers=AUTH)
        assert answer.status_code == 400 and "not a finite number" in answer.json()["error"], body
    step = client.post("/api/play/step", json={"play": "nope", "action": [0] * 6}, headers=AUTH)
    assert step.status_code == 404
    started = client.post("/api/play/start", json={"level": level}, headers=AUTH).json()
    for action in ([3, 0, 0, 0, 0, 0], [0] * 5, "left", [True, 0, 0, 0, 0, 0]):
        answer = client.post("/api/play/step", json={"play": started["play"], "action": action}, headers=AUTH)
        assert answer.status_code == 400 and answer.json()["error"].startswith("action:")
    assert client.post("/api/check", json={"level": level}, headers=AUTH).json()["ok"]


def test_a_check_says_what_kinetix_validate_says_on_the_entity_and_field(client, level):
    good = client.post("/api/check", json={"level": level}, headers=AUTH).json()
    assert good["ok"] and good["size"] == "s" and len(good["slots"]) == len(level["bodies"])
    shapes = {s["slot"]: s for s in good["scene"]["shapes"]}
    assert shapes[good["slots"][0]]["fill"] == [0, 204, 0]  # the green chassis, in render's colours
    assert [text for text, _ in good["scene"]["legend"]] == ["M2", "T1"]
    broken = json.loads(json.dumps(level))
    broken["bodies"][1]["radius"] = -1
    answer = client.post("/api/check", json={"level": broken}, headers=AUTH).json()
    with pytest.raises(LevelError) as validate:
        parse_level(broken, "level")
    assert not answer["ok"] and f"level: {answer['error']}" == str(validate.value)
    assert (answer["entity"], answer["field"], answer["also"]) == ("bodies[1]", "radius", [])
    twin = json.loads(json.dumps(level))
    twin["bodies"][2]["name"] = twin["bodies"][0]["name"]
    answer = client.post("/api/check", json={"level": twin}, headers=AUTH).json()
    assert (answer["entity"], answer["field"], answer["also"]) == ("bodies[2]", "name", ["bodies[0]"])


def test_files_are_listed_and_bad_ones_named(client):
    files = {f["path"]: f for f in client.get("/api/files", headers=AUTH).json()["files"]}
    assert files[LEVEL]["valid"] and files[LEVEL]["name"] == "rocket car jump"
    assert not files["latin1.json"]["valid"] and "not UTF-8" in files["latin1.json"]["error"]
    assert "link.json" not in files
    answer = client.get("/api/level", params={"path": "latin1.json"}, headers=AUTH)
    assert answer.status_code == 422 and answer.json()["error"] == "latin1.json: not UTF-8 text (byte 13)"
    thumbnail = client.get("/api/thumbnail", params={"path": LEVEL}, headers=AUTH)
    assert thumbnail.headers["content-type"] == "image/png" and thumbnail.content[:4] == b"\x89PNG"


def test_saving_never_overwrites_without_confirmation_nor_a_valid_level_with_a_draft(client, folder, level):
    before = (folder / LEVEL).read_bytes()
    answer = client.post("/api/save", json={"path": LEVEL, "level": level}, headers=AUTH)
    assert answer.status_code == 409 and "confirm" in answer.json()["error"]
    draft = level | {"bodies": []}  # invalid: a level needs bodies
    answer = client.post("/api/save", json={"path": LEVEL, "level": draft, "overwrite": True}, headers=AUTH)
    assert answer.status_code == 409 and "invalid draft" in answer.json()["error"]
    assert (folder / LEVEL).read_bytes() == before
    (folder / "drafts").mkdir()
    kept = client.post("/api/save", json={"path": "drafts/wip.json", "level": draft}, headers=AUTH).json()
    assert kept == {"path": "drafts/wip.json", "valid": False, "error": kept["error"]} and kept["error"]
    assert json.loads((folder / "drafts" / "wip.json").read_text()) == draft
    answer = client.post("/api/save", json={"path": "drafts/wip.txt", "level": level}, headers=AUTH)
    assert answer.status_code == 400


def test_a_played_episode_that_solves_the_level_becomes_its_solution(client, folder, level):
    started = client.post("/api/play/start", json={"level": level}, headers=AUTH).json()
    assert started["step"] == 0 and started["ending"] is None
    kept = client.post("/api/play/solution", json={"play": started["play"], "level": level}, headers=AUTH)
    assert kept.status_code == 409  # not solved yet
    actions = decode_solution(level["solution"], LEVEL, 256)
    for action in actions:
        frame = client.post("/api/play/step", json={"play": started["play"], "action": action.tolist()}, headers=AUTH)
        frame = frame.json()
        if frame["ending"]:
            break
    assert frame["ending"] == "solved" and frame["return"] > 0.9
    assert frame["scene"]["thrusters"][0]["action"] == 1.0  # the frame shows the thruster firing
    played = dict(level)
    del played["solution"]
    kept = client.post("/api/play/solution", json={"play": started["play"], "level": played}, headers=AUTH).json()
    saved = client.post("/api/save", json={"path": "played.json", "level": kept["level"]}, headers=AUTH).json()
    assert saved["valid"]
    outcome = check_level(load_level(folder / "played.json"))  # what `kinetix validate --play` replays
    assert bool(outcome["solution"].solved[0])


def test_several_steps_in_one_request_and_the_oldest_episode_dropped(client, level):
    first = client.post("/api/play/start", json={"level": level}, headers=AUTH).json()["play"]
    one = {"play": first, "action": [0] * 6}
    frame = client.post("/api/play/step", json=one | {"steps": 8}, headers=AUTH).json()
    assert frame["step"] == 8 and frame["seconds"] == pytest.approx(8 * frame["step_seconds"], abs=1e-9)  # [s]
    for steps in (0, 9, 1.5, True):
        assert client.post("/api/play/step", json=one | {"steps": steps}, headers=AUTH).status_code == 400
    for _ in range(MAX_EPISODES):
        client.post("/api/play/start", json={"level": level}, headers=AUTH)
    gone = client.post("/api/play/step", json=one, headers=AUTH)
    assert gone.status_code == 404 and "start again" in gone.json()["error"]


@pytest.fixture(scope="module")
def agent_run(folder, tiny_run):
    """The session's tiny run, copied into the studio's folder (an agent is a shipped name or a run in it)."""
    return shutil.copytree(tiny_run, folder / "runs" / "tiny").relative_to(folder).as_posix()


def test_an_agent_plays_the_level_and_is_evaluated_with_the_finetune_command(client, folder, level, agent_run):
    started = client.post("/api/watch/start", json={"level": level, "agent": agent_run, "seed": 1}, headers=AUTH)
    started = started.json()
    assert started["step"] == 0 and started["scene"]["shapes"] and started["step_seconds"] > 0
    frames = [started]
    while not frames[-1]["ending"] and len(frames) < 300:  # live: one step per request, the agent choosing
        frames.append(client.post("/api/play/step", json={"play": started["play"]}, headers=AUTH).json())
    assert frames[-1]["ending"] in ("solved", "failed", "timed out") and 2 <= len(frames) <= 257
    assert [f["step"] for f in frames] == list(range(len(frames)))
    assert frames[-1]["return"] == pytest.approx(sum(f["reward"] for f in frames), abs=1e-4)
    refused = [
        client.post("/api/play/step", json={"play": started["play"], "action": [0] * 6}, headers=AUTH),
        client.post("/api/play/solution", json={"play": started["play"], "level": level}, headers=AUTH),
    ]
    assert [r.status_code for r in refused] == [400, 409]
    assert "its agent chooses" in refused[0].json()["error"] and "its own settings" in refused[1].json()["error"]
    result = client.post(
        "/api/evaluate", json={"level": level, "agent": agent_run, "attempts": 3, "path": LEVEL}, headers=AUTH
    ).json()
    assert result["attempts"] == 3 and 0 <= result["solve_rate"] <= 1
    here = lambda name: os.path.relpath(folder / name)  # noqa: E731  the command runs where the studio started
    command = [
        "kinetix",
        "finetune",
        here(LEVEL),
        "--from",
        here(agent_run),
        "--run-dir",
        "runs/finetune-rocket-car-jump",
    ]
    assert shlex.split(result["finetune"]) == command
    missing = client.post("/api/watch/start", json={"level": level, "agent": "runs/none"}, headers=AUTH)
    assert missing.status_code == 422 and "runs/none" in missing.json()["error"]


@pytest.mark.slow
def test_generated_and_mutated_levels_are_valid(client, level):
    for size in ("s", "m"):
        made = client.post("/api/generate", json={"size": size, "seed": 5}, headers=AUTH).json()["level"]
        assert client.post("/api/check", json={"level": made}, headers=AUTH).json()["size"] == size
    edited = client.post("/api/mutate", json={"level": level, "seed": 3, "edits": 4}, headers=AUTH).json()["level"]
    assert client.post("/api/check", json={"level": edited}, headers=AUTH).json()["ok"] and edited != level
    assert client.post("/api/generate", json={"size": "xl"}, headers=AUTH).status_code == 400


def test_a_reference_level_opens_through_the_importer_with_its_notes(client, folder):
    shutil.copy(REFERENCE_LEVELS / "m" / "arm_up.json", folder / "arm_up.json")  # the paper's format
    answer = client.get("/api/level", params={"path": "arm_up.json"}, headers=AUTH).json()
    assert answer["level"]["format"] == "kinetix-level/1" and answer["check"]["ok"]
    assert any("joint 1: b_relative_pos" in note for note in answer["notes"])


def test_a_request_for_another_host_is_refused_whatever_its_token(folder):
    app = create_app(Studio(folder), TOKEN, port=PORT, hosts=("studio.example",))
    for host in ("evil.example", "evil.example:8765", "127.0.0.2", "localhost.evil.example"):
        answer = TestClient(app, base_url=f"http://{host}").get("/api/files", headers=AUTH)
        assert answer.status_code == 403 and "localhost only" in answer.json()["error"], host
        assert TestClient(app, base_url=f"http://{host}").get("/", params={"token": TOKEN}).status_code == 403
    for host in ("localhost", "localhost:8765", "127.0.0.1:8765", "[::1]:8765", "LOCALHOST", "studio.example:80"):
        assert TestClient(app, base_url=f"http://{host}").get("/api/files", headers=AUTH).status_code == 200, host


def test_the_session_cookie_is_named_after_the_port_so_two_studios_keep_their_own(folder):
    first, second = (
        TestClient(create_app(Studio(folder), t, port=p), base_url=LOCAL) for t, p in (("one", 1), ("two", 2))
    )
    page = first.get("/", params={"token": "one"})
    assert page.cookies.get(cookie_name(1)) == "one" and cookie_name(1) != cookie_name(2)
    second.cookies.set(cookie_name(1), "one")  # the other studio's cookie, as the browser holds both
    assert second.get("/static/studio.js").status_code == 403
    assert first.get("/static/studio.js").status_code == 200


def test_a_file_that_cannot_be_shown_is_a_4xx_naming_the_file_and_field(client):
    for url in ("/api/level", "/api/thumbnail"):
        answer = client.get(url, params={"path": "nan.json"}, headers=AUTH)
        assert answer.status_code == 422 and answer.headers["content-type"] == "application/json", url
        assert answer.json()["error"].startswith("nan.json: bodies[0].position[0]: not a finite number")
    listed = {f["path"]: f for f in client.get("/api/files", headers=AUTH).json()["files"]}
    assert not listed["nan.json"]["valid"] and "bodies[0].position[0]" in listed["nan.json"]["error"]
    assert ".hidden.json" not in listed
    assert client.get("/api/level", params={"path": ".hidden.json"}, headers=AUTH).status_code == 403


def test_a_draft_is_saved_only_as_a_level_object_of_finite_numbers_in_a_folder_that_exists(client, folder, level):
    refused = [
        ({"path": "s.json", "level": "a bare string"}, 400, "expected a JSON object"),
        ({"path": "s.json", "level": {"junk": "x" * 1000}}, 400, "format"),
        ({"path": "s.json", "level": level | {"junk": "x" * MAX_LEVEL_BYTES}}, 413, "at most"),
        ({"path": "new-folder/s.json", "level": level}, 404, "no such folder"),
        ({"path": "%2e%2e/outside/pwn.json", "level": level}, 400, "plain characters"),
        ({"path": ".hidden-save.json", "level": level}, 403, "hidden"),
        ({"path": "-rf.json", "level": level}, 400, "option"),
    ]
    for body, status, message in refused:
        answer = client.post("/api/save", json=body, headers=AUTH)
        assert answer.status_code == status and message in answer.json()["error"], body["path"]
    nan = b'{"path": "s.json", "level": {"format": "kinetix-level/1", "gravity": [0, NaN]}}'
    assert client.post("/api/save", content=nan, headers=AUTH).status_code == 400
    assert not (folder / "s.json").exists() and not (folder / "new-folder").exists()
    assert not (folder / "%2e%2e").exists() and not (folder / ".hidden-save.json").exists()


def test_evaluate_checks_its_arguments_before_it_evaluates_and_quotes_the_command(
    client, folder, level, agent_run, monkeypatch
):
    runs = []
    real = service.Evaluator
    monkeypatch.setattr(service, "Evaluator", lambda *args: runs.append(args) or real(*args))
    ask = {"level": level, "agent": agent_run, "attempts": 1}
    for path, status in (("../x.json", 403), ("/etc/passwd", 403), (7, 400)):
        assert client.post("/api/evaluate", json=ask | {"path": path}, headers=AUTH).status_code == status, path
    assert client.post("/api/evaluate", json=ask | {"attempts": 0}, headers=AUTH).status_code == 400
    assert client.post("/api/evaluate", json=ask | {"agent": "../runs/tiny"}, headers=AUTH).status_code == 403
    assert runs == []  # refused before any evaluation ran
    (folder / "x; echo PWNED; y.json").write_text(json.dumps(level))  # a name a user may have given it
    result = client.post("/api/evaluate", json=ask | {"path": "x; echo PWNED; y.json"}, headers=AUTH).json()
    assert len(runs) == 1 and shlex.split(result["finetune"])[2] == os.path.relpath(folder / "x; echo PWNED; y.json")


def test_a_client_that_goes_away_mid_request_is_not_an_error(client, capsys):
    messages = iter([{"type": "http.request", "body": b'{"level": ', "more_body": True}, {"type": "http.disconnect"}])
    sent = []

    async def receive():
        return next(messages)

    async def send(message):
        sent.append(message)

    headers = [(b"host", b"localhost"), (TOKEN_HEADER.lower().encode(), TOKEN.encode())]
    scope = {"type": "http", "method": "POST", "path": "/api/check", "headers": headers, "query_string": b""}
    asyncio.run(client.app(scope | {"http_version": "1.1", "scheme": "http", "root_path": ""}, receive, send))
    assert sent[0]["status"] == 400 and "Traceback" not in capsys.readouterr().err
