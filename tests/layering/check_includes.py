#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The floors (README, "Floors"): every `#include "ROOM/..."` in the project's code points
to its own floor or one below. Usage: check_includes.py [ROOT]; prints each include that
points up as FILE:LINE: the include, the room and what that room may use; exit 1 if any.
Inside host/ the rooms have an order of their own (HOST_ORDER, issue 38 §2)."""
import pathlib
import re
import sys

# A room (path prefix, most specific first) and the rooms it may include. The firmware core
# (signal, plan, runlog, engine) does no I/O: it may not use hal, nor firmware/app.
FIRMWARE_CORE = ("firmware/signal", "firmware/plan", "firmware/runlog", "firmware/engine")
FLOORS = [
    ("base/", ("base",)),
    ("hal/", ("base", "hal")),
    ("firmware/app/", ("base", "hal", "firmware")),
    ("firmware/", ("base",) + FIRMWARE_CORE),
    ("sim/", ("base", "hal", "firmware", "sim")),
    ("host/", ("base", "hal", "firmware", "sim", "host")),
]
# host/'s own floors, lowest first (README, "Floors"; host/README.md): a host room may include
# its own headers and those of the host rooms on a lower floor, never one beside it or above.
# A host room not listed here is named as such: a new room gets its floor here.
HOST_ORDER = [
    ("process", "output", "measures", "import", "multisine"),
    ("design",),
    ("identify", "simulate"),
    ("export",),
    ("campaign",),
    ("montecarlo", "loop"),
    ("adaptive",),
    ("cli",),
]
# A header's file is ROOM/include/ROOM/NAME.hpp and its spelling ROOM/NAME.hpp: both start
# with the room, so a file and what it includes map to rooms the same way. Include roots that
# are not a room's path: hal's public interface folder.
ALIASES = {"excite/hal/": "hal/"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def room_of(path):
    for prefix, allowed in FLOORS:
        if path.startswith(prefix):
            return prefix, allowed
    return None, None


def host_room(path):
    """The host room of a path or include ("host/identify/x.hpp" -> "identify"), else None."""
    parts = path.split("/")
    return parts[1] if len(parts) > 2 and parts[0] == "host" else None


def host_floor(room):
    for floor, rooms in enumerate(HOST_ORDER):
        if room in rooms:
            return floor
    return None


def host_violation(room, target):
    """Why `room` (a host room) may not include `target`, or None when it may."""
    used = host_room(target)
    if used is None or used == room:
        return None
    mine = host_floor(room)
    if mine is None:
        return f"host/{room} is not in host's order (tests/layering/check_includes.py, HOST_ORDER)"
    theirs = host_floor(used)
    if theirs is not None and theirs < mine:
        return None
    below = sorted(r for rooms in HOST_ORDER[:mine] for r in rooms)
    return (f"host/{room} may use host/" + ", host/".join(below) if below
            else f"host/{room} may use no other host room")


def sources(root):
    """The C++ files of the floors' rooms (tests, toolchain and packaging may use them all)."""
    for top in sorted({prefix.split("/")[0] for prefix, _ in FLOORS}):
        for source in sorted((root / top).rglob("*")):
            if source.suffix in (".cpp", ".hpp", ".h"):
                yield source


def violations(root, files):
    found = []
    for source in files:
        relative = source.relative_to(root).as_posix()
        room, allowed = room_of(relative)
        for number, line in enumerate(source.read_text(errors="replace").splitlines(), 1):
            match = INCLUDE.match(line)
            if not match:
                continue
            target = match.group(1)
            for alias, real in ALIASES.items():
                if target.startswith(alias):
                    target = real + target[len(alias):]
            if "/" not in target:
                continue  # a file beside this one
            if not any(target.startswith(a + "/") for a in allowed):
                found.append(f"{relative}:{number}: #include \"{match.group(1)}\" points up: "
                             f"{room} may use {', '.join(allowed)}")
            elif room == "host/" and host_room(relative):
                why = host_violation(host_room(relative), target)
                if why:
                    found.append(f"{relative}:{number}: #include \"{match.group(1)}\" points "
                                 f"up: {why}")
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    files = list(sources(root))
    found = violations(root, files)
    for v in found:
        print(v)
    print(f"check_includes: {len(found)} include(s) pointing up in {len(files)} files of {root}")
    if not files:
        print("check_includes: no C++ file under base/, hal/, firmware/, sim/ or host/")
        return 1
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
