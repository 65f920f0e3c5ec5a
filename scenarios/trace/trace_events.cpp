#include "scenarios/trace/trace_events.h"

#include "models/plumbing/config_error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace rcsim::trace {

std::string micros(std::uint64_t ps) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%llu.%06llu", static_cast<unsigned long long>(ps / 1000000),
                  static_cast<unsigned long long>(ps % 1000000));
    return buf;
}

std::string quoted(const std::string& s) {
    std::string o = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\';
            o += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
            o += buf;
        } else {
            o += c;
        }
    }
    return o + "\"";
}

TraceEventWriter::TraceEventWriter(const std::string& path) : path_(path), out_(path, std::ios::binary) {
    if (!out_) throw ConfigError(path, 0, std::string("cannot write the trace file: ") + std::strerror(errno));
    out_ << "{\"displayTimeUnit\":\"ns\",\"traceEvents\":[\n";
}

void TraceEventWriter::event(const std::string& body) {
    if (failed_ || closed_) return;
    if (!first_) out_ << ",\n";
    first_ = false;
    out_ << '{' << body << '}';
    ++events_;
    if (!out_) {
        failed_ = true;
        error_ = errno;
    }
}

namespace {
std::string ids(unsigned pid, unsigned tid) {
    return "\"pid\":" + std::to_string(pid) + ",\"tid\":" + std::to_string(tid);
}
} // namespace

void TraceEventWriter::process_name(unsigned pid, const std::string& name, int sort) {
    event("\"ph\":\"M\",\"name\":\"process_name\"," + ids(pid, 0) + ",\"args\":{\"name\":" + quoted(name) + "}");
    event("\"ph\":\"M\",\"name\":\"process_sort_index\"," + ids(pid, 0) + ",\"args\":{\"sort_index\":" +
          std::to_string(sort) + "}");
}

void TraceEventWriter::thread_name(unsigned pid, unsigned tid, const std::string& name, int sort) {
    event("\"ph\":\"M\",\"name\":\"thread_name\"," + ids(pid, tid) + ",\"args\":{\"name\":" + quoted(name) + "}");
    event("\"ph\":\"M\",\"name\":\"thread_sort_index\"," + ids(pid, tid) + ",\"args\":{\"sort_index\":" +
          std::to_string(sort) + "}");
}

void TraceEventWriter::complete(unsigned pid, unsigned tid, const std::string& name, std::uint64_t ts_ps,
                                std::uint64_t dur_ps, const std::string& args) {
    event("\"ph\":\"X\",\"name\":" + quoted(name) + "," + ids(pid, tid) + ",\"ts\":" + micros(ts_ps) +
          ",\"dur\":" + micros(dur_ps) + (args.empty() ? "" : ",\"args\":{" + args + "}"));
}

void TraceEventWriter::instant(unsigned pid, unsigned tid, const std::string& name, std::uint64_t ts_ps) {
    event("\"ph\":\"i\",\"s\":\"t\",\"name\":" + quoted(name) + "," + ids(pid, tid) + ",\"ts\":" + micros(ts_ps));
}

void TraceEventWriter::counter(unsigned pid, const std::string& name, std::uint64_t ts_ps, std::int64_t value) {
    event("\"ph\":\"C\",\"name\":" + quoted(name) + "," + ids(pid, 0) + ",\"ts\":" + micros(ts_ps) +
          ",\"args\":{\"value\":" + std::to_string(value) + "}");
}

void TraceEventWriter::close() {
    if (closed_) return;
    if (!failed_) {
        out_ << "\n]}\n";
        out_.flush();
        if (!out_) {
            failed_ = true;
            error_ = errno;
        }
    }
    out_.close();
    closed_ = true;
    if (failed_)
        throw ConfigError(path_, 0, std::string("cannot write the trace file: ") +
                                        std::strerror(error_ ? error_ : EIO));
}

} // namespace rcsim::trace
