#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A PLC stand-in built on pymodbus (Debian's python3-pymodbus), not on our code.

Serves Modbus TCP on 127.0.0.1 (an ephemeral port, printed as "listening 127.0.0.1:PORT"),
with every holding and input register 0..999 at zero (zero-based addresses), and acts like
a PLC program: each time the heartbeat holding register changes it copies it into the
heartbeat echo input register and records the setpoints it holds at that moment (float32,
word order ABCD) as one CSV row "heartbeat,sp0,sp1,...". On SIGTERM it writes the rows to
--record and exits 0.

usage: pymodbus_plc.py --setpoints N --setpoint-base A --heartbeat H --echo E --record FILE
"""
import argparse
import asyncio
import signal
import socket
import struct
import sys

from pymodbus.datastore import (ModbusSequentialDataBlock, ModbusServerContext,
                                ModbusSlaveContext)
from pymodbus.server import StartAsyncTcpServer


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--setpoints", type=int, required=True)
    ap.add_argument("--setpoint-base", type=int, required=True)
    ap.add_argument("--heartbeat", type=int, required=True)
    ap.add_argument("--echo", type=int, required=True)
    ap.add_argument("--record", required=True)
    a = ap.parse_args()

    store = ModbusSlaveContext(hr=ModbusSequentialDataBlock(0, [0] * 1000),
                               ir=ModbusSequentialDataBlock(0, [0] * 1000), zero_mode=True)
    context = ModbusServerContext(slaves=store, single=True)
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    rows = []

    async def plc_program(stop):
        last = None
        while not stop.is_set():
            hb = store.getValues(3, a.heartbeat, 1)[0]
            if hb != last:
                last = hb
                store.setValues(4, a.echo, [hb])
                regs = store.getValues(3, a.setpoint_base, 2 * a.setpoints)
                sps = [struct.unpack(">f", struct.pack(">HH", regs[2 * i], regs[2 * i + 1]))[0]
                       for i in range(a.setpoints)]
                rows.append(",".join([str(hb)] + [repr(v) for v in sps]))
            await asyncio.sleep(0.0005)

    async def run():
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        loop.add_signal_handler(signal.SIGTERM, stop.set)
        server = await StartAsyncTcpServer(context, address=("127.0.0.1", port), defer_start=True)
        serving = asyncio.create_task(server.serve_forever())
        await asyncio.sleep(0.2)
        print(f"listening 127.0.0.1:{port}", flush=True)
        await plc_program(stop)
        with open(a.record, "w") as out:
            out.write("\n".join(rows) + "\n")
        await server.shutdown()
        serving.cancel()

    asyncio.run(run())
    return 0


if __name__ == "__main__":
    sys.exit(main())
