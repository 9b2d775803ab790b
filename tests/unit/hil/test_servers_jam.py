"""No client can jam the control socket or the dashboard (docs/hil.md, faults at run time), while
a paced 1-car run without BCU (the safe state) goes on: idle connections cannot lock the operator
out, a huge or negative body is refused before it is read, and many thousands of malformed requests
are each answered with an error, never a traceback, while the loop keeps stepping. Everything on
127.0.0.1."""

import json
import random
import socket
import threading
import time

import pytest

from conftest import SECRET
from railbrake import hil
from railbrake.hil import guard
from railbrake.hil.control import MAX_LINE, ControlServer
from railbrake.hil.dashboard import Dashboard

FUZZ = 10_000   # malformed requests per server


def under_attack(attack):
    """A paced run with a control socket and a dashboard sharing one token; attack(control, board)
    runs in a thread once both are up (its return value is returned with the run's result), then the
    run stops. Also the loop's step before and after the attack."""
    board = Dashboard(cars=1)
    servers, outcome, done = [], {}, threading.Event()

    def worker():
        try:
            while board.view is None or board.view.read() is None:
                time.sleep(0.01)
            outcome["step_before"] = board.view.read()["step"]
            outcome["value"] = attack(servers[0], board)
            outcome["step_after"] = board.view.read()["step"]
        except Exception as exc:   # noqa: BLE001 - reported by the test
            outcome["error"] = repr(exc)
        finally:
            done.set()

    threads = []

    def on_faults(switch):
        board.attach(switch=switch)
        servers.append(ControlServer(switch, token=board.token))
        threads.append(threading.Thread(target=worker))
        threads[-1].start()

    try:
        result = hil.run("emergency-300-heavy-rain", ("127.0.0.1", 9), cars=1, duration=120.0, priority=0,
                         key=SECRET, on_faults=on_faults, on_live=lambda view: board.attach(view=view),
                         stop=done.is_set)
    finally:
        for thread in threads:
            thread.join()
        for server in servers:
            server.stop()
        board.close()
    assert "error" not in outcome, outcome["error"]
    return result, outcome, servers[0], board


def connect(port):
    return socket.create_connection(("127.0.0.1", port), timeout=10)


def ask(sock, line: bytes) -> dict:
    sock.sendall(line + b"\n")
    data = b""
    while not data.endswith(b"\n"):
        chunk = sock.recv(65536)
        if not chunk:
            raise ConnectionError(f"closed after {data!r}")
        data += chunk
    return json.loads(data)


def rss_kb() -> int:
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


def http(port, raw: bytes) -> bytes:
    """Sends a raw request and ends the sending side (a request cut short is all there is), returns
    the whole answer (the server closes after an error)."""
    data = b""
    with connect(port) as sock:
        try:
            sock.sendall(raw)
            sock.shutdown(socket.SHUT_WR)
        except OSError:   # the server answered and closed before taking all of it (a refused body)
            pass
        try:
            while chunk := sock.recv(65536):
                data += chunk
        except ConnectionResetError:   # closed with the rest of the body unread: the answer came before
            pass
    return data


@pytest.mark.slow   # the Python servers' connection limits, not the core
def test_idle_connections_do_not_lock_the_operator_out():
    def attack(control, board):
        idle = [connect(control.port) for _ in range(50)]
        idle_http = [connect(board.port) for _ in range(50)]
        time.sleep(0.3)   # all accepted (or already closed to make room)
        with connect(control.port) as operator:
            reply = ask(operator, json.dumps({"token": control.token, "command": "faults"}).encode())
        status = http(board.port, f"GET /api/info HTTP/1.0\r\nAuthorization: Bearer {board.token}\r\n\r\n".encode())
        for sock in idle + idle_http:
            sock.close()
        return reply, status, control.guard.evicted, board.guard.evicted

    result, outcome, control, board = under_attack(attack)
    reply, status, evicted_control, evicted_board = outcome["value"]
    first_line = status.split(b"\r\n")[0]
    print(f"operator: {reply}; dashboard: {first_line!r}; closed to make room: control "
          f"{evicted_control}, dashboard {evicted_board}")
    assert reply == {"ok": True, "changes": []}
    assert status.startswith(b"HTTP/1.0 200") and b'"cars": 1' in status
    assert evicted_control >= 50 + 1 - guard.MAX_PER_PEER and evicted_board >= 50 + 1 - guard.MAX_PER_PEER
    assert outcome["step_after"] > outcome["step_before"]


def test_a_huge_or_negative_body_is_refused_before_it_is_read():
    token = None

    def attack(control, board):
        nonlocal token
        token = board.token
        before = rss_kb()
        answers = {}
        for name, length in (("huge", "314572800"), ("negative", "-1"), ("text", "abc"), ("huge_digits", "9" * 40)):
            for auth in (f"Authorization: Bearer {token}\r\n", ""):
                head = (f"POST /api/fault HTTP/1.1\r\nHost: x\r\n{auth}Content-Type: application/json\r\n"
                        f"Content-Length: {length}\r\n\r\n").encode()
                answers[name, bool(auth)] = http(board.port, head + b"{" * 65536)   # 64 kB of the body only
        return answers, rss_kb() - before

    result, outcome, control, board = under_attack(attack)
    answers, growth_kb = outcome["value"]
    print(f"memory growth {growth_kb} kB;", {k: v.split(b"\r\n")[0].decode() for k, v in answers.items()})
    assert growth_kb < 10 * 1024
    assert answers["huge", True].startswith(b"HTTP/1.0 413") and b"at most 4096 bytes" in answers["huge", True]
    assert answers["huge_digits", True].startswith(b"HTTP/1.0 413")
    for name in ("negative", "text"):
        assert answers[name, True].startswith(b"HTTP/1.0 400") and b"Content-Length" in answers[name, True]
    for name in ("huge", "negative", "text", "huge_digits"):   # no token: refused before the length matters
        assert answers[name, False].startswith(b"HTTP/1.0 401")
    assert board.guard.unexpected == 0


def malformed_lines(rng, token):
    """Control lines that are all wrong in some way (never a valid command)."""
    kinds = [
        lambda: bytes(rng.randrange(1, 256) for _ in range(rng.randrange(1, 200))).replace(b"\n", b" "),
        lambda: b"[" * rng.randrange(20, 4000),
        lambda: b'{"a":' * rng.randrange(10, 800),
        lambda: json.dumps({"token": token, "command": "inject", "fault": rng.choice(
            [[], 5, "x", None, {"type": "vent_stuck_open", "car": rng.choice([0, 99, -1, "1", 1.5, None])},
             {"type": "no_such_kind", "car": 1}, {"type": {"a": [1]}, "car": 1}])}).encode(),
        lambda: json.dumps({"token": rng.choice([5, None, [], "wrong", token * 3]), "command": "faults"}).encode(),
        lambda: json.dumps({"token": token, "command": rng.choice([1, [], {}, "explode", None]), "x": 1}).encode(),
        lambda: json.dumps({"token": token, "command": "faults", "extra" * rng.randrange(1, 300): 1}).encode(),
        lambda: rng.choice([b"1e999999", b"NaN", b'"\\ud800"', b"{}", b"[]", b"null", b"\xff\xfe", b"{" + b"}" * 9]),
        lambda: b"x" * rng.randrange(MAX_LINE + 1, 3 * MAX_LINE),
    ]
    while True:
        yield rng.choice(kinds)()


def fuzz_control(control, count):
    rng, answered, errors = random.Random(41), 0, 0
    lines = malformed_lines(rng, control.token)
    with connect(control.port) as sock:
        reader = sock.makefile("rb")
        while answered < count:
            batch = [next(lines) for _ in range(50)]
            sock.sendall(b"".join(line + b"\n" for line in batch))
            for _ in batch:
                reply = json.loads(reader.readline())
                answered += 1
                errors += reply["ok"] is False and bool(reply["error"])
    return answered, errors


BAD_LENGTHS = ['-5', 'x', '1e3', '', '99999999999999999', '0x10', ' 12', '12, 13']


def malformed_requests(rng, token):
    """HTTP requests that are all wrong in some way."""
    paths = ["/api/fault", "/api/stop", "/api/snapshot", "/api/info", "/nope", "/" + "a" * 3000, "/api/fault?token=x"]
    auth = ["Authorization: Bearer wrong\r\n", "Authorization: Basic abc\r\n", "", f"Authorization: {token}\r\n",
            f"Authorization: Bearer {token}x\r\n"]   # never the right one: every request here is refused
    kinds = [
        lambda: bytes(rng.randrange(0, 256) for _ in range(rng.randrange(1, 300))),
        lambda: f"{rng.choice(['GET', 'POST', 'PUT', 'BREW', 'DELETE'])} {rng.choice(paths)} HTTP/1.0\r\n"
                f"{rng.choice(auth)}\r\n".encode(),
        lambda: (f"POST /api/fault HTTP/1.0\r\nAuthorization: Bearer {token}\r\nContent-Length: "
                 f"{rng.choice(BAD_LENGTHS)}\r\n\r\n").encode(),
        lambda: (lambda body: f"POST /api/fault HTTP/1.0\r\nAuthorization: Bearer {token}\r\nContent-Length: "
                 f"{len(body)}\r\n\r\n".encode() + body)(rng.choice(
                     [b"[" * 3000, b"not json", b'{"command": "inject", "fault": []}', b"\xff" * 10,
                      b'{"command": "inject", "fault": {"type": "vent_stuck_open", "car": 77}}', b"{" * 4000])),
        lambda: b"GET / HTTP/1.0\r\n" + b"X: y\r\n" * rng.randrange(101, 120) + b"\r\n",
        lambda: b"GET /api/info HTTP/9.9\r\n\r\n",
        lambda: f"GET /api/info?{'&'.join('a=b' for _ in range(200))} HTTP/1.0\r\n\r\n".encode(),
        lambda: (f"POST /api/stop HTTP/1.0\r\nContent-Length: 5\r\nContent-Length: 7\r\nAuthorization: Bearer "
                 f"{token}\r\n\r\nhello").encode(),
    ]
    while True:
        yield rng.choice(kinds)()


def fuzz_dashboard(board, count, clients=4):
    rng, lock = random.Random(42), threading.Lock()
    requests = malformed_requests(rng, board.token)
    statuses, sent = {}, [0]

    def client():
        while True:
            with lock:
                if sent[0] >= count:
                    return
                sent[0] += 1
                raw = next(requests)
            answer = http(board.port, raw)
            status = answer[9:12].decode() if answer.startswith(b"HTTP/") else "none"
            with lock:
                statuses[status] = statuses.get(status, 0) + 1

    threads = [threading.Thread(target=client) for _ in range(clients)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return statuses


@pytest.mark.slow
def test_malformed_requests_are_answered_never_a_traceback(capfd):
    def attack(control, board):
        t0 = time.monotonic()
        answered, errors = fuzz_control(control, FUZZ)
        t1 = time.monotonic()
        statuses = fuzz_dashboard(board, FUZZ)
        return answered, errors, statuses, t1 - t0, time.monotonic() - t1

    result, outcome, control, board = under_attack(attack)
    answered, errors, statuses, control_s, board_s = outcome["value"]
    err = capfd.readouterr().err
    print(f"control: {answered} lines in {control_s:.1f} s, {errors} errors; dashboard: {sum(statuses.values())} "
          f"requests in {board_s:.1f} s, statuses {statuses}; loop steps {outcome['step_before']} -> "
          f"{outcome['step_after']}, overruns {result.counters['overruns']}")
    assert answered == errors == FUZZ
    assert sum(statuses.values()) == FUZZ and "none" not in statuses and "500" not in statuses
    assert set(statuses) <= {"400", "401", "404", "411", "413", "414", "431", "501", "505", "409"}
    assert "Traceback" not in err and control.guard.unexpected == 0 and board.guard.unexpected == 0
    assert outcome["step_after"] > outcome["step_before"]   # the loop stepped on throughout
    assert not result.interrupted or result.counters["steps"] >= outcome["step_after"]
    assert result.fault_changes == []                        # nothing of it changed a fault
