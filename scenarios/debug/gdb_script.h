// rcsim — the gdb Python script rcsim writes beside symbols.elf (scenarios/debug/rcsim_gdb.py): a
// real-mode unwinder, so that gdb's `bt`, `up` and `finish` follow the 8086's frames (docs/tools.md
// "gdb"). The text is the .py file itself, made a C++ string at configure time.
#pragma once

namespace rcsim::debug {

extern const char* const kGdbUnwinderScript;

} // namespace rcsim::debug
