"""The link recovers from any network (ICD v4, docs/hil-interface.md, handshake): a plant and the
reference BCU process talk through a UDP proxy on 127.0.0.1 that cuts the traffic for whole outages
and, in between, drops, delays (up to 200 ms, so reorders), duplicates and replays frames and
challenges. Each stretch of the safe state lasts at most its outage plus 1 s, no replayed frame is
received and no key is taken twice or from a challenge the plant did not ask for.

The soak lasts RAILBRAKE_HIL_SOAK_S s (default 15; minutes for a bench run)."""

import heapq
import json
import os
import random
import select
import socket
import struct
import threading
import time

import numpy as np
import pytest

from railbrake import hil
from railbrake.hil.frames import frame_header
from conftest import SECRET

SCENARIO = "emergency-300-heavy-rain"
DT = 1e-3
HOLD = 0.1   # s, the plant's hold time (its default)
SOAK_S = float(os.environ.get("RAILBRAKE_HIL_SOAK_S", "15"))


class Proxy(threading.Thread):
    """Forwards plant <-> BCU. Outages are windows of plant steps [a, b) in which every datagram is
    dropped. replay_first: as traffic returns after each outage, the session's first challenge is
    sent to the plant ahead of the BCU's real one. rng: random impairments on every other datagram
    (drop, delay up to 200 ms, duplicate, replay an earlier datagram of the same direction)."""

    def __init__(self, bcu_port, outages, replay_first=False, rng=None):
        super().__init__(daemon=True)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 21)
        self.port = self.sock.getsockname()[1]
        self.bcu, self.plant = ("127.0.0.1", bcu_port), None
        self.outages, self.replay_first, self.rng = outages, replay_first, rng
        self.plant_step, self.done = 0, False
        self.first_challenge, self.returning = None, False
        self.queue, self.order = [], 0          # (due, order, data, to): delayed datagrams
        self.history = {"plant": [], "bcu": []}  # what each side sent (for replays), bounded
        self.plant_frames = []                   # header of every plant frame (hellos and keyed ones)
        self.delivered = set()                   # distinct BCU command frames handed to the plant
        self.replayed_challenges = self.replays = self.duplicates = self.dropped = self.delayed = 0

    def in_outage(self):
        return any(a <= self.plant_step < b for a, b in self.outages)

    def send(self, data, to, delay=0.0):
        if delay > 0.0:
            heapq.heappush(self.queue, (time.monotonic() + delay, self.order, data, to))
            self.order += 1
            return
        if to != self.bcu and data[5] == 2:
            self.delivered.add(bytes(data))
        self.sock.sendto(data, to)

    def impaired(self, data, to, side):
        """Random impairments (soak): drop, delay, duplicate, and replay one of the last 2000."""
        rng, history = self.rng, self.history[side]
        if rng.random() < 0.02 and history:
            self.send(history[rng.randrange(len(history))], to, rng.uniform(0.0, 0.2))
            self.replays += 1
        history.append(data)
        if len(history) > 2000:
            del history[:1000]
        if rng.random() < 0.05:
            self.dropped += 1
            return
        copies = 2 if rng.random() < 0.05 else 1
        self.duplicates += copies - 1
        for _ in range(copies):
            delay = rng.uniform(0.0, 0.2) if rng.random() < 0.2 else 0.0
            self.delayed += delay > 0.0
            self.send(data, to, delay)

    def from_bcu(self, data):
        challenge = len(data) > 5 and data[5] == 3
        if challenge and self.first_challenge is None:
            self.first_challenge = data
        if self.in_outage():
            return
        if challenge and self.returning and self.replay_first:
            self.sock.sendto(self.first_challenge, self.plant)   # ahead of the real one
            self.replayed_challenges += 1
            self.returning = False
        if self.rng is None:
            self.send(data, self.plant)
        else:
            self.impaired(data, self.plant, "bcu")

    def from_plant(self, data):
        was_out = self.in_outage()
        self.plant_step = struct.unpack_from("<Q", data, 20)[0]
        if len(self.plant_frames) < 10 ** 6:
            self.plant_frames.append(frame_header(data))
        if self.in_outage():
            return
        self.returning = self.returning or was_out
        if self.rng is None:
            self.send(data, self.bcu)
        else:
            self.impaired(data, self.bcu, "plant")

    def release(self):
        now = time.monotonic()
        while self.queue and self.queue[0][0] <= now:
            _, _, data, to = heapq.heappop(self.queue)
            self.send(data, to)

    def run(self):
        while not self.done:
            self.release()
            if not select.select([self.sock], [], [], 0.002)[0]:
                continue
            for _ in range(256):   # what is waiting, then the due ones again
                try:
                    data, sender = self.sock.recvfrom(4096, socket.MSG_DONTWAIT)
                except BlockingIOError:
                    break
                if sender == self.bcu:
                    if self.plant is not None:
                        self.from_bcu(data)
                else:
                    self.plant = sender
                    self.from_plant(data)


def through(proxy, duration):
    proxy.start()
    try:
        return hil.run(SCENARIO, ("127.0.0.1", proxy.port), cars=1, duration=duration, hold_time=HOLD,
                       record_interval=DT, priority=0, key=SECRET)
    finally:
        proxy.done = True
        proxy.join()
        proxy.sock.close()


def safe_stretches(result):
    """[first, last] steps of each stretch of the safe state after the first handshake."""
    safe = np.asarray(result.outputs["safe_state"]) > 0.5
    steps = np.round(np.asarray(result.outputs["time"]) / DT).astype(int)
    start = int(np.argmax(~safe))   # the first handshake: safe until the first valid frame
    edges = np.flatnonzero(np.diff(safe[start:].astype(int))) + start + 1
    bounds = np.concatenate(([start], edges, [len(safe)]))
    return [(int(steps[a]), int(steps[b - 1])) for a, b in zip(bounds[:-1], bounds[1:]) if safe[a]]


def check_bound(stretches, outages):
    """Each safe stretch lies within an outage's start and its end plus 1 s (the hold time after the
    last valid frame before it, the handshake after it); none outside an outage."""
    for first, last in stretches:
        around = [(a, b) for a, b in outages if a <= first <= b + 1000]
        assert around, f"safe state at steps {first}..{last} outside any outage {outages}"
        a, b = around[0]
        assert last - first + 1 <= (b - a) + 1000, f"safe {first}..{last} for the outage {a}..{b}"


def check_keys(frames):
    """From the plant's own frames: each session key (BCU nonce, plant nonce) comes from a plant nonce
    it offered in a hello before, each plant nonce keys once, and a key left is never taken again."""
    offered, keys, current = set(), [], None
    for h in frames:
        if h["nonce"] == 0:
            offered.add(h["plant_nonce"])
            continue
        key = (h["nonce"], h["plant_nonce"])
        if key != current:
            assert key not in keys, f"key {key} taken again"
            assert h["plant_nonce"] in offered, f"key {key}: plant nonce never offered in a hello"
            keys.append(key)
            current = key
    assert len({p for _, p in keys}) == len(keys)
    return keys


def served(bcu):
    bcu.terminate()
    return json.loads(bcu.communicate(timeout=60)[0])


OUTAGES = [(1000, 1800), (3000, 3800)]   # steps: 0.8 s each


@pytest.mark.slow
def test_replayed_first_challenge_costs_nothing(bcu_process):
    """The reproducer of issue 41: traffic dropped twice and, as it returns, the session's first
    challenge replayed ahead of the BCU's real one. The plant refuses it (it echoes a hello nonce no
    longer offered), takes the real one, and is in the safe state no longer than without the replay."""
    results = {}
    for replay in (False, True):
        bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "5")
        proxy = Proxy(port, OUTAGES, replay_first=replay)
        result = through(proxy, 5.0)
        stretches = safe_stretches(result)
        c = result.counters
        print(f"replay {replay}: received {c['received']}, safe steps {c['safe_state_steps']}, stretches "
              f"{stretches}, hellos {c['hellos']}, stale challenges {c['stale_challenges']}, "
              f"replayed {proxy.replayed_challenges}")
        check_bound(stretches, OUTAGES)
        assert len(stretches) == len(OUTAGES)
        check_keys(proxy.plant_frames)
        if replay:
            assert proxy.replayed_challenges == len(OUTAGES)
            assert c["stale_challenges"] >= proxy.replayed_challenges   # each refused
        served(bcu)
        results[replay] = c
    # frames received as without the replay: at most a BCU cycle or two apart per outage (10 ms each)
    assert results[True]["received"] >= results[False]["received"] - 5 * len(OUTAGES)


@pytest.mark.slow
def test_impairment_soak(bcu_process):
    """Outages every 3 s (0.3 to 1.5 s long) and, between them, 5 % dropped, 20 % delayed up to
    200 ms, 5 % duplicated and 2 % replays of earlier frames, hellos and challenges in both directions."""
    rng = random.Random(41)
    outages, step = [], 2000
    while step < SOAK_S * 1000 - 2500:
        length = rng.randrange(300, 1500)
        outages.append((step, step + length))
        step += length + 3000
    bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "5")
    proxy = Proxy(port, outages, rng=rng)
    result = through(proxy, SOAK_S)
    c = result.counters
    stretches = safe_stretches(result)
    print(f"soak {SOAK_S} s: outages {outages}; stretches {stretches}; proxy dropped {proxy.dropped}, delayed "
          f"{proxy.delayed}, duplicated {proxy.duplicates}, replayed {proxy.replays}; plant {c}")
    check_bound(stretches, outages)
    keys = check_keys(proxy.plant_frames)
    assert len(keys) >= len(outages) + 1                    # a new key after each outage
    # no replayed frame is received: at most the distinct command frames that reached the plant
    assert c["received"] <= len(proxy.delivered)
    assert c["duplicate"] + c["replayed"] + c["forged"] + c["stale_challenges"] > 0   # replays came
    assert c["malformed"] == 0
    counters = served(bcu)
    assert counters["malformed"] == 0 and counters["forged"] == 0
