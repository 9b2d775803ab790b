"""A HIL server full of authenticated connections answers a newcomer with its busy message and
closes it (hil.guard.Guarded, shared by the control socket and the dashboard); the operator's own
connection stays served."""

import socket
import socketserver
import threading

from railbrake.hil import guard


def test_a_newcomer_gets_the_busy_answer_when_all_connections_are_authenticated():
    guard_ = guard.Guard(max_connections=1, max_per_peer=1)
    admitted = threading.Event()

    class Handler(socketserver.StreamRequestHandler):
        def handle(self):
            guard_.active(self.request, authenticated=True)
            admitted.set()
            self.rfile.readline()   # served until the client closes
            guard_.release(self.request)

    class Server(guard.Guarded, socketserver.ThreadingTCPServer):
        daemon_threads = True
        guard, name, busy = guard_, "test", b"busy\n"

    server = Server(("127.0.0.1", 0), Handler)
    thread = threading.Thread(target=server.serve_forever)
    thread.start()
    try:
        with socket.create_connection(server.server_address, timeout=5) as operator:
            assert admitted.wait(5)
            with socket.create_connection(server.server_address, timeout=5) as newcomer:
                assert newcomer.makefile("rb").readline() == b"busy\n"
                assert newcomer.recv(1) == b""                    # then closed
            assert guard_.refused == 1 and guard_.evicted == 0 and guard_.count() == 1
            operator.sendall(b"\n")
    finally:
        server.shutdown()
        server.server_close()
        thread.join()
