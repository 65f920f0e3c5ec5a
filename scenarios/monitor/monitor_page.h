// rcsim — the monitor's live page (page.html, built into the binary: the server needs no file
// beside it, and the page needs no network but the server's own WebSocket).
#pragma once

namespace rcsim::monitor {

extern const char* const kMonitorPage;

} // namespace rcsim::monitor
