# rcsim's gdb unwinder for the communication board's 8086 (docs/tools.md "gdb"): real-mode frames,
# so that `bt`, `up` and `finish` work. rcsim writes this file beside symbols.elf; gdb loads it
# with `source DIR/rcsim-gdb.py` (the line rcsim prints says so).
#
# gdb's own i8086 unwinder knows neither segments nor the 8086's 16-bit return addresses: from any
# function it found the caller at 0x00000000. This one reads the frames as the firmware builds them:
#   - a C function (bcc): `push bp; mov bp,sp` on entry, then [BP] = the caller's BP, [BP+2] = the
#     return IP (a near call: the caller's CS);
#   - before that point, or in an assembly routine without a BP frame, the stack as the routine's
#     entry left it: its instructions from the entry to the pc are read (pushes, pops, `dec sp`,
#     `inc sp`, moves and the like; a jump or an instruction it does not know ends the reading,
#     and then a BP a little above SP is taken as a BP frame, else the frame is not unwound);
#   - an interrupt handler (a routine the interrupt vector table points to): the 8086 pushed FLAGS,
#     CS and IP, so the caller is CS:IP from the stack, anywhere in memory.
# Addresses are linear (the stub's pc is CS*16 + IP; the stack is at SS*16 + SP).
import re

import gdb
from gdb.unwinder import Unwinder, register_unwinder


class _FrameId:
    """A frame's identity for gdb: its stack address and its function (gdb.Value, as gdb reads them)."""

    def __init__(self, sp, pc):
        self.sp = gdb.Value(sp)
        self.pc = gdb.Value(pc)


def _u16(addr):
    return int.from_bytes(bytes(gdb.selected_inferior().read_memory(addr, 2)), "little")


def _code(addr, n):
    return bytes(gdb.selected_inferior().read_memory(addr, n))


def _function_start(pc):
    """The start of the code symbol holding pc (`info symbol`), or None."""
    text = gdb.execute("info symbol %d" % pc, to_string=True)
    m = re.match(r"(\S+)(?: \+ (\d+))? in section", text)
    if not m or not m.group(1):
        return None
    return pc - int(m.group(2) or 0)


def _interrupt_handlers():
    """Linear addresses the interrupt vector table (0000:0000, 256 x IP, CS) points to."""
    table = _code(0, 1024)
    return {int.from_bytes(table[4 * v + 2:4 * v + 4], "little") * 16 +
            int.from_bytes(table[4 * v:4 * v + 2], "little") for v in range(256)}


# Straight-line instructions a routine's entry uses, by opcode: (length, change of SP). A ModRM
# instruction's length comes from its ModRM byte (None here).
_SIMPLE = {op: (1, -2) for op in list(range(0x50, 0x58)) + [0x06, 0x0E, 0x16, 0x1E, 0x9C]}  # push
_SIMPLE.update({op: (1, +2) for op in list(range(0x58, 0x60)) + [0x07, 0x17, 0x1F, 0x9D]})  # pop
_SIMPLE.update({0x4C: (1, -1), 0x44: (1, +1)})  # dec sp, inc sp
_SIMPLE.update({op: (1, 0) for op in [0xFA, 0xFB, 0xFC, 0xFD, 0xF8, 0xF9, 0x90, 0x98, 0x99,
                                      0xEC, 0xED, 0xEE, 0xEF] + list(range(0x40, 0x44)) +
                list(range(0x45, 0x4C)) + list(range(0x4D, 0x50))})  # flags, nop, in/out dx, inc/dec
_SIMPLE.update({op: (2, 0) for op in list(range(0xB0, 0xB8)) + [0xE4, 0xE6, 0x3C, 0x24, 0x0C, 0x34, 0x04, 0x2C, 0xA8]})
_SIMPLE.update({op: (3, 0) for op in list(range(0xB8, 0xC0)) + [0x3D, 0x25, 0x0D, 0x35, 0x05, 0x2D, 0xA9, 0xA0, 0xA1, 0xA2, 0xA3]})
_MODRM = {0x88, 0x89, 0x8A, 0x8B, 0x8C, 0x8E, 0x8D, 0x30, 0x31, 0x32, 0x33, 0x00, 0x01, 0x02, 0x03,
          0x28, 0x29, 0x2A, 0x2B, 0x38, 0x39, 0x3A, 0x3B, 0x20, 0x21, 0x22, 0x23, 0x08, 0x09, 0x0A, 0x0B,
          0x84, 0x85}


def _modrm_length(modrm):
    mod, rm = modrm >> 6, modrm & 7
    if mod == 3:
        return 2
    if mod == 0:
        return 4 if rm == 6 else 2
    return 3 if mod == 1 else 4


_MAX_ENTRY_READ = 512


def _entry_state(start, pc):
    """(SP change from the entry to pc, offset of the caller's BP below the entry SP or None,
    whether `mov bp,sp` ran right after `push bp`) for the straight-line code start..pc; None
    when an instruction on the way is one this reading does not follow."""
    if not 0 <= pc - start <= _MAX_ENTRY_READ:
        return None  # no entry is this long without a jump: the symbol is not this code's
    code = _code(start, pc - start + 6)
    at, sp, saved_bp = 0, 0, None
    while at < pc - start:
        op = code[at]
        if op == 0x55 and code[at + 1:at + 3] in (b"\x89\xe5", b"\x8b\xec") and at + 3 <= pc - start:
            return sp - 2, sp - 2, True  # push bp; mov bp,sp: from here on, BP holds the frame
        if op in _SIMPLE:
            length, delta = _SIMPLE[op]
            if op == 0x55:
                saved_bp = sp - 2
        elif op in _MODRM:
            modrm = code[at + 1]
            writes_sp = (op == 0x8B and (modrm >> 3 & 7) == 4) or (op == 0x89 and modrm >> 6 == 3 and modrm & 7 == 4)
            if writes_sp:
                return None  # mov sp,...: the stack moves where this reading cannot follow
            length, delta = _modrm_length(modrm), 0
        elif op == 0xE8:
            length, delta = 3, 0  # a call returns with SP as it was
        else:
            return None
        at, sp = at + length, sp + delta
    return sp, saved_bp, False


def _interrupted_at(ss, sp):
    """Where the 8086 left IP, CS and FLAGS for an interrupt handler whose own pushes this reading
    could not follow: the first such triple above SP whose FLAGS have bits 12-15 set (the 8086
    pushes them as 1s) and whose CS:IP is in a function gdb knows. The offset from SP, or None."""
    words = _code(ss * 16 + sp, 2 * 34)
    w = [int.from_bytes(words[2 * i:2 * i + 2], "little") for i in range(34)]
    for i in range(32):
        ip, cs, flags = w[i], w[i + 1], w[i + 2]
        if flags & 0xF000 == 0xF000 and _function_start(cs * 16 + ip) is not None:
            return 2 * i
    return None


class RealModeUnwinder(Unwinder):
    def __init__(self):
        super().__init__("rcsim real mode")

    def __call__(self, pending):
        try:
            return self._unwind(pending)
        except gdb.MemoryError:
            return None  # memory the stub does not serve: this frame is gdb's own to show

    def _unwind(self, pending):
        pc = int(pending.read_register("eip")) & 0xFFFFF
        cs = int(pending.read_register("cs")) & 0xFFFF
        ss = int(pending.read_register("ss")) & 0xFFFF
        sp = int(pending.read_register("esp")) & 0xFFFF
        bp = int(pending.read_register("ebp")) & 0xFFFF
        start = _function_start(pc)
        if start is None:
            return None
        state = _entry_state(start, pc)
        handler = start in _interrupt_handlers()
        if state is None and handler:
            found = _interrupted_at(ss, sp)
            state = None if found is None else (-found, None, False)
        elif state is None and sp < bp < sp + 0x400:
            # The reading stopped (a jump, or a start the map gives wrong: a static C function has
            # no public name): every C function of the firmware keeps its BP frame, so a BP a
            # little above SP is taken as this frame's.
            state = (0, None, True)
        if state is not None and state[2]:
            ret_sp, caller_bp = (bp + 2) & 0xFFFF, _u16(ss * 16 + bp)  # BP frame: [BP], [BP+2]
        elif state is not None:
            delta, saved_bp, _ = state
            ret_sp = (sp - delta) & 0xFFFF  # SP at the entry: the return address
            caller_bp = bp if saved_bp is None else _u16(ss * 16 + ((sp - delta + saved_bp) & 0xFFFF))
        else:
            return None
        ret_ip = _u16(ss * 16 + ret_sp)
        if handler:
            caller_cs, caller_sp = _u16(ss * 16 + ret_sp + 2), ret_sp + 6  # IP, CS, FLAGS
        else:
            caller_cs, caller_sp = cs, ret_sp + 2
        caller_pc = caller_cs * 16 + ret_ip
        if caller_pc == 0 or caller_pc == pc and caller_sp == sp:
            return None
        info = pending.create_unwind_info(_FrameId(ss * 16 + ret_sp, start))
        for name, value in (("eip", caller_pc), ("cs", caller_cs), ("esp", caller_sp & 0xFFFF),
                            ("ebp", caller_bp), ("ss", ss)):
            # Each of the register's own type and size (32 bits in the i386 core feature).
            info.add_saved_register(name, gdb.Value(value).cast(pending.read_register(name).type))
        return info


register_unwinder(None, RealModeUnwinder(), replace=True)
