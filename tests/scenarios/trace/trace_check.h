// rcsim tests — an independent validator of a Trace Event Format file, by the format's rules
// (the Trace Event Format document that chrome://tracing and ui.perfetto.dev implement):
//   - the document is {"traceEvents":[...]} (or a bare array) of objects with "ph", "pid";
//   - slices and instants live on a thread track (pid, tid), counters on (pid, name);
//   - on every track, timestamps never decrease in file order (the writer promises it: the
//     viewer then needs no sort to nest slices correctly);
//   - B/E pairs balance per thread track (each E closes the innermost open B, names equal when
//     the E has one, none left open at the end); X slices have a duration >= 0 and nest: one
//     that starts inside another on its track also ends inside it;
//   - counters carry numeric args.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace rcsim::test {

/// Every rule broken, one line each (at most `limit`); empty = a valid trace.
std::vector<std::string> check_trace(const nlohmann::json& doc, std::size_t limit = 20);

/// The events of a trace, however it is wrapped.
const nlohmann::json& trace_events(const nlohmann::json& doc);

/// Thread names from the metadata events: (pid, tid) -> name.
std::map<std::pair<long, long>, std::string> thread_names(const nlohmann::json& doc);

} // namespace rcsim::test
