#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A Modbus client built on pymodbus (Debian's python3-pymodbus), not on our code.

Drives excite-plant's default register map by hand: writes setpoint 0 (float32 ABCD at
holding --setpoint-base), then the heartbeat --samples times (one lock-step sample each),
reads the heartbeat echo and the outputs, and prints "echo OUT0 OUT1 ..." on one line.

usage: pymodbus_client.py --port P --setpoint-base A --heartbeat H --echo E --outputs M
                          --output-base B --value V --samples K
"""
import argparse
import struct
import sys

from pymodbus.client import ModbusTcpClient


def main():
    ap = argparse.ArgumentParser()
    for name in ("--port", "--setpoint-base", "--heartbeat", "--echo", "--outputs",
                 "--output-base", "--samples"):
        ap.add_argument(name, type=int, required=True)
    ap.add_argument("--value", type=float, required=True)
    a = ap.parse_args()
    client = ModbusTcpClient("127.0.0.1", port=a.port)
    if not client.connect():
        print("cannot connect", file=sys.stderr)
        return 1
    hi, lo = struct.unpack(">HH", struct.pack(">f", a.value))
    if client.write_registers(a.setpoint_base, [hi, lo], slave=1).isError():
        print("write setpoint failed", file=sys.stderr)
        return 1
    for k in range(1, a.samples + 1):
        if client.write_registers(a.heartbeat, [k], slave=1).isError():
            print("write heartbeat failed", file=sys.stderr)
            return 1
    echo = client.read_input_registers(a.echo, 1, slave=1)
    outs = client.read_input_registers(a.output_base, 2 * a.outputs, slave=1)
    if echo.isError() or outs.isError():
        print("read failed", file=sys.stderr)
        return 1
    r = outs.registers
    ys = [struct.unpack(">f", struct.pack(">HH", r[2 * j], r[2 * j + 1]))[0]
          for j in range(a.outputs)]
    print(" ".join([str(echo.registers[0])] + [repr(y) for y in ys]))
    client.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
