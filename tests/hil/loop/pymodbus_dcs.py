#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A DCS stand-in built on pymodbus (Debian's python3-pymodbus), not on our code, for the
gateway in closed loop (issue 42 §3): its controller output plus the gateway's test offset is
what the plant gets.

Serves Modbus TCP on 127.0.0.1 (an ephemeral port, printed as "listening 127.0.0.1:PORT") at
the addresses of excite-plant's closed-loop default map for 2 MVs and 2 CVs
(sim/server/README.md, "Closed loop"; zero-based), so that the gateway.toml of
`excite loop-config --plant woodberry2x2 --controller FILE` streams to it unchanged:

  holding 500, 502   MV test offsets (float32 ABCD, written by the gateway, read back)
  holding 504, 506   CV setpoint offsets
  holding 508        heartbeat (uint16); its echo at input 300
  holding 410        the operator's switch: 1 control (at start), 0 manual
  input 200, 202     the CVs y (float32)
  input 500, 502     the controller's output uc (fixed: --uc)
  input 504, 506     the applied MV = clamp(uc + offset, +-limit)
  input 508, 510     the CV setpoints in force (the setpoint offsets)
  input 512, 513     MV status: 0 ok, 1 clamped low, 2 clamped high, 4 manual
  input 514          mode: 0 off (manual), 1 control, 2 test (an offset is not zero)

Each scan (1 ms): the heartbeat echoed; the heartbeat unchanged for --watchdog-s returns
every offset to zero (the DCS drops the offsets; the controller stays in control); the CVs
follow G(0) of Wood and Berry's column times the applied MVs with a first-order lag. Each
heartbeat change records "heartbeat,o1,o2,sp1,sp2"; on SIGTERM the rows and a last row
"final,o1,o2,sp1,sp2,mode" are written to --record and the process exits 0.

usage: pymodbus_dcs.py --record FILE [--uc A B] [--limit L] [--watchdog-s S]
"""
import argparse
import asyncio
import signal
import socket
import struct
import sys
import time

from pymodbus.datastore import (ModbusSequentialDataBlock, ModbusServerContext,
                                ModbusSlaveContext)
from pymodbus.server import StartAsyncTcpServer

OFFSETS, HEARTBEAT, ECHO, SWITCH = 500, 508, 300, 410
Y, UC, APPLIED, YSP, STATUS, MODE = 200, 500, 504, 508, 512, 514
G0 = ((12.8, -18.9), (6.6, -19.4))  # Wood and Berry's column, steady-state gains


def to_float(hi, lo):
    return struct.unpack(">f", struct.pack(">HH", hi, lo))[0]


def to_regs(x):
    return list(struct.unpack(">HH", struct.pack(">f", x)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--record", required=True)
    ap.add_argument("--uc", type=float, nargs=2, default=[0.1, -0.05])
    ap.add_argument("--limit", type=float, default=1.0)
    ap.add_argument("--watchdog-s", type=float, default=1.0)
    a = ap.parse_args()

    store = ModbusSlaveContext(hr=ModbusSequentialDataBlock(0, [0] * 1000),
                               ir=ModbusSequentialDataBlock(0, [0] * 1000), zero_mode=True)
    store.setValues(3, SWITCH, [1])
    context = ModbusServerContext(slaves=store, single=True)
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    rows = []

    def offsets():
        r = store.getValues(3, OFFSETS, 8)
        return [to_float(r[2 * k], r[2 * k + 1]) for k in range(4)]

    async def dcs_program(stop):
        last_hb, changed_at, seen = None, time.monotonic(), False
        y = [0.0, 0.0]
        held = list(a.uc)
        while not stop.is_set():
            now = time.monotonic()
            hb = store.getValues(3, HEARTBEAT, 1)[0]
            if hb != last_hb:
                seen = seen or last_hb is not None
                last_hb, changed_at = hb, now
                store.setValues(4, ECHO, [hb])
                rows.append(",".join([str(hb)] + [repr(v) for v in offsets()]))
            elif seen and now - changed_at > a.watchdog_s and any(v != 0.0 for v in offsets()):
                store.setValues(3, OFFSETS, [0] * 8)  # the watchdog: every offset to zero
            o = offsets()
            manual = store.getValues(3, SWITCH, 1)[0] == 0
            applied, status = [], []
            for i in range(2):
                if manual:
                    applied.append(held[i])
                    status.append(4)
                    continue
                u = a.uc[i] + o[i]
                status.append(1 if u < -a.limit else 2 if u > a.limit else 0)
                applied.append(min(max(u, -a.limit), a.limit))
            held = applied
            for j in range(2):
                target = G0[j][0] * applied[0] + G0[j][1] * applied[1]
                y[j] += 0.05 * (target - y[j])
            mode = 0 if manual else 2 if any(v != 0.0 for v in o) else 1
            store.setValues(4, Y, to_regs(y[0]) + to_regs(y[1]))
            store.setValues(4, UC, to_regs(a.uc[0]) + to_regs(a.uc[1]))
            store.setValues(4, APPLIED, to_regs(applied[0]) + to_regs(applied[1]))
            store.setValues(4, YSP, to_regs(o[2]) + to_regs(o[3]))
            store.setValues(4, STATUS, status + [mode])
            await asyncio.sleep(0.001)

    async def run():
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        loop.add_signal_handler(signal.SIGTERM, stop.set)
        server = await StartAsyncTcpServer(context, address=("127.0.0.1", port), defer_start=True)
        serving = asyncio.create_task(server.serve_forever())
        await asyncio.sleep(0.2)
        print(f"listening 127.0.0.1:{port}", flush=True)
        await dcs_program(stop)
        mode = store.getValues(4, MODE, 1)[0]
        rows.append(",".join(["final"] + [repr(v) for v in offsets()] + [str(mode)]))
        with open(a.record, "w") as out:
            out.write("\n".join(rows) + "\n")
        await server.shutdown()
        serving.cancel()

    asyncio.run(run())
    return 0


if __name__ == "__main__":
    sys.exit(main())
