#!/usr/bin/env python3
"""A static HTTP server whose link slows down on a schedule: a test's narrow network.

Usage: throttled_http.py PORT DIR SCHEDULE
SCHEDULE is SECONDS=BYTES_PER_SECOND pairs, comma-separated, timed from the first request
("0=0,4=60000": unlimited for 4 s, then 60000 bytes/s; 0 is unlimited). The limit is shared by
every connection (one link). Each request is logged on stderr as http.server does.
"""
import functools
import http.server
import sys
import threading
import time


class Link:
    """Paces the bytes sent by every connection to the schedule's rate (a token bucket of 16 kB)."""

    def __init__(self, schedule):
        self.schedule = sorted(schedule)
        self.start = None
        self.lock = threading.Lock()
        self.step = -1
        self.step_start = 0.0
        self.sent = 0
        self.burst = 16384  # bytes a link that was idle may send at once

    def rate(self, now):
        t = now - self.start
        step = max(i for i, (at, _) in enumerate(self.schedule) if at <= t)
        if step != self.step:
            self.step, self.step_start, self.sent = step, now, 0
        return self.schedule[step][1]

    def first_request(self):
        with self.lock:
            if self.start is None:
                self.start = time.monotonic()

    def wait(self, n):
        with self.lock:
            now = time.monotonic()
            rate = self.rate(now)
            if rate <= 0:
                return
            if self.step_start + self.sent / rate < now - self.burst / rate:
                # An idle link saves no credit beyond one burst: no catching up at full speed.
                self.step_start, self.sent = now - self.burst / rate, 0
            self.sent += n
            due = self.step_start + self.sent / rate
        if due > now:
            time.sleep(due - now)


class Handler(http.server.SimpleHTTPRequestHandler):
    link = None
    chunk = 4096

    def do_GET(self):
        self.link.first_request()
        super().do_GET()

    def copyfile(self, source, outputfile):
        while True:
            buf = source.read(self.chunk)
            if not buf:
                return
            self.link.wait(len(buf))
            outputfile.write(buf)


def main():
    port, root, schedule = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    pairs = [tuple(float(x) for x in p.split("=")) for p in schedule.split(",")]
    if not any(at == 0 for at, _ in pairs):
        pairs.append((0.0, 0.0))
    Handler.link = Link(pairs)
    handler = functools.partial(Handler, directory=root)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", port), handler)
    server.daemon_threads = True
    server.serve_forever()


if __name__ == "__main__":
    main()
