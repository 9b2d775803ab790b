"""An on-path attacker between the plant and the reference BCU process (ICD v3, docs/hil-interface.md,
threat model): a relay that both sides talk through, which duplicates, swaps and replays the BCU's
frames, and later replays a whole recorded session. The plant's counters stay exact (received + lost
= the BCU's frames up to the newest received) and a replayed session cannot capture the BCU."""

import json
import select
import socket
import struct
import threading
import time

from railbrake import hil
from railbrake.hil.frames import frame_header
from conftest import SECRET

SCENARIO = "emergency-300-heavy-rain"
FRAMES = 120   # the relay passes this many of the BCU's frames (however long a loaded machine takes),
TAIL = 400     # then none, while the plant runs on for this many steps


class Relay(threading.Thread):
    """Forwards plant -> BCU and BCU -> plant, recording the plant's frames. BCU command frames k = 0,
    1, ...: k % 5 == 1 is held back and sent after the next (a pair swap), k % 7 == 3 is sent twice,
    every 13th is followed by a copy of the frame sent 70 before (older than the plant's window of 64)
    and every 17th by a copy of the one 10 before (inside it)."""

    def __init__(self, bcu_port, faults=True):
        super().__init__(daemon=True)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.bcu, self.plant, self.faults = ("127.0.0.1", bcu_port), None, faults
        self.recorded, self.sent, self.held = [], [], None
        self.swaps = self.duplicates = self.replays_old = self.replays_recent = 0
        self.max_forwarded, self.plant_step, self.done, self.cut_step = -1, 0, False, None

    def to_plant(self, data):
        self.sock.sendto(data, self.plant)
        self.max_forwarded = max(self.max_forwarded, frame_header(data)["sequence"])

    def bcu_frame(self, data):
        h = frame_header(data)
        if h["type"] != "bcu" or not self.faults:
            self.sock.sendto(data, self.plant)
            return
        if len(self.sent) >= FRAMES:
            self.cut_step = self.cut_step or self.plant_step
            return
        k = len(self.sent)
        self.sent.append(data)
        if k % 5 == 1:
            self.held = data
            self.swaps += 1
            return
        self.to_plant(data)
        if self.held is not None:
            self.to_plant(self.held)
            self.held = None
        if k % 7 == 3:
            self.to_plant(data)
            self.duplicates += 1
        if k % 13 == 12 and k >= 70:
            self.sock.sendto(self.sent[k - 70], self.plant)
            self.replays_old += 1
        if k % 17 == 16:
            self.sock.sendto(self.sent[k - 10], self.plant)
            self.replays_recent += 1

    def run(self):
        while not self.done:
            if not select.select([self.sock], [], [], 0.05)[0]:
                continue
            data, sender = self.sock.recvfrom(2048)
            if sender == self.bcu:
                self.bcu_frame(data)
            else:
                self.plant = sender
                self.plant_step = struct.unpack_from("<Q", data, 20)[0]
                self.recorded.append(data)
                self.sock.sendto(data, self.bcu)


def through(relay, duration, **kwargs):
    relay.start()
    try:
        return hil.run(SCENARIO, ("127.0.0.1", relay.port), cars=1, duration=duration, priority=0, key=SECRET,
                       **kwargs)
    finally:
        relay.done = True
        relay.join()


def test_counters_stay_exact_under_duplication_swaps_and_replay(bcu_process):
    bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "0.5")
    relay = Relay(port)
    result = through(relay, 60.0, hold_time=1.0,
                     stop=lambda: relay.cut_step is not None and relay.plant_step >= relay.cut_step + TAIL)
    c = result.counters
    print(f"relay: swaps {relay.swaps}, duplicates {relay.duplicates}, replays {relay.replays_old} old, "
          f"{relay.replays_recent} recent; plant: {c}")
    assert relay.swaps > 15 and relay.duplicates > 10 and relay.replays_old >= 3 and relay.replays_recent >= 3
    # every BCU frame up to the newest the plant got is received or lost: exactly
    assert c["received"] + c["lost"] == relay.max_forwarded + 1
    assert c["lost"] == 0 and c["forged"] == 0 and c["malformed"] == 0 and c["late"] == 0
    assert c["out_of_order"] == relay.swaps                       # the older of each pair: not applied
    assert c["duplicate"] == relay.duplicates + relay.replays_recent
    assert c["replayed"] == relay.replays_old
    assert result.loss["lost"] is False
    served = json.loads(bcu.communicate(timeout=60)[0])   # one session key: numbered 0 .. sent - 1
    assert served["sent"] >= relay.max_forwarded + 1 and served["forged"] == 0


def test_a_replayed_session_cannot_capture_the_bcu(bcu_process):
    """Run 1 through the relay records every plant frame (hellos and keyed ones). After the BCU's
    session has gone idle, the relay replays them all, from the address the BCU knew run 1 by, while
    run 2 starts: the BCU serves run 2 from its first steps, and counts the replay as foreign."""
    bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "5")
    relay = Relay(port, faults=False)
    first = through(relay, 0.5)
    assert first.counters["received"] > 30
    time.sleep(1.2)   # run 1's session is idle: another plant may open one

    def replay():
        for data in relay.recorded:
            relay.sock.sendto(data, ("127.0.0.1", port))
            time.sleep(0.0005)

    replayer = threading.Thread(target=replay)
    replayer.start()
    second = hil.run(SCENARIO, ("127.0.0.1", port), cars=1, duration=1.0, priority=0, key=SECRET)
    replayer.join()
    c = second.counters
    assert c["received"] > 80 and c["safe_state_steps"] < 50 and second.loss["lost"] is False
    bcu.terminate()
    served = json.loads(bcu.communicate(timeout=60)[0])
    keyed = sum(1 for data in relay.recorded if frame_header(data)["nonce"])
    # run 1's keyed frames: stale while run 1's session is the BCU's (the BCU does not go back in time,
    # nor does a replay keep it from going idle), foreign (an old nonce) once run 2's is
    assert served["foreign"] + served["stale"] >= keyed
    relay.sock.close()
