#!/usr/bin/env python3
"""Measures an emulated link from its two ends: `echo PORT` answers UDP
datagrams and TCP connections on PORT; `probe ADDRESS PORT COUNT INTERVAL_S`
sends COUNT timestamped UDP datagrams and one TCP exchange, then prints JSON:
round trips (p50/p99/min/max ms), loss share, and the TCP connect + echo time.
For netlab tests: what the link emulator does must be what a socket sees."""
import json
import socket
import sys
import threading
import time


def echo(port):
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    udp.bind(("0.0.0.0", port))
    tcp = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    tcp.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    tcp.bind(("0.0.0.0", port))
    tcp.listen(4)

    def serve_tcp():
        while True:
            conn, _ = tcp.accept()
            with conn:
                data = conn.recv(65536)
                while data:
                    conn.sendall(data)
                    data = conn.recv(65536)

    threading.Thread(target=serve_tcp, daemon=True).start()
    while True:
        data, peer = udp.recvfrom(2048)
        udp.sendto(data, peer)


def percentile(values, q):
    ordered = sorted(values)
    return ordered[max(0, min(len(ordered) - 1, int(-(-q * len(ordered) // 1)) - 1))]


def probe(address, port, count, interval_s):
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    udp.settimeout(0.001)
    sent = {}
    rtts = []
    start = time.monotonic()
    for i in range(count):
        now = time.monotonic()
        sent[i] = now
        udp.sendto(i.to_bytes(4, "big") + bytes(60), (address, port))
        deadline = start + (i + 1) * interval_s
        while time.monotonic() < deadline:
            try:
                data, _ = udp.recvfrom(2048)
                rtts.append(time.monotonic() - sent[int.from_bytes(data[:4], "big")])
            except socket.timeout:
                pass
    drain_until = time.monotonic() + 2.0
    while time.monotonic() < drain_until and len(rtts) < count:
        try:
            data, _ = udp.recvfrom(2048)
            rtts.append(time.monotonic() - sent[int.from_bytes(data[:4], "big")])
        except socket.timeout:
            pass
    t0 = time.monotonic()
    tcp = socket.create_connection((address, port), timeout=10)
    connected = time.monotonic()
    payload = bytes(100_000)
    tcp.sendall(payload)
    got = 0
    while got < len(payload):
        got += len(tcp.recv(65536))
    done = time.monotonic()
    tcp.close()
    ms = [r * 1e3 for r in rtts]
    print(json.dumps({
        "sent": count, "received": len(rtts), "loss": 1.0 - len(rtts) / count,
        "rtt_ms": {"min": min(ms), "p50": percentile(ms, 0.5), "p99": percentile(ms, 0.99), "max": max(ms)} if ms else None,
        "tcp_connect_ms": (connected - t0) * 1e3, "tcp_echo_100k_ms": (done - connected) * 1e3,
    }))


if __name__ == "__main__":
    if sys.argv[1] == "echo":
        echo(int(sys.argv[2]))
    else:
        probe(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]))
