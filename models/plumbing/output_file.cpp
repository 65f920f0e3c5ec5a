// rcsim — a file a run writes. See output_file.h.
#include "models/plumbing/output_file.h"

#include "models/plumbing/config_error.h"

#include <cerrno>
#include <cstring>

namespace rcsim {

OutputFile::OutputFile(std::filesystem::path path, std::string what)
    : path_(std::move(path)), what_(std::move(what)) {
    errno = 0;
    out_.open(path_, std::ios::binary);
    if (!out_) fail(errno);
}

void OutputFile::fail(int err) const {
    std::string why = "cannot write " + what_;
    if (err != 0) why += std::string(": ") + std::strerror(err);
    throw ConfigError(path_.string(), 0, why);
}

void OutputFile::check() {
    if (out_) out_.flush();
    if (!out_) fail(errno);
}

void OutputFile::close() {
    // A write that already failed left its reason in errno (best effort: later calls may have
    // replaced it; the file is named either way).
    if (!out_) fail(errno);
    errno = 0;
    out_.flush();
    const bool flushed = static_cast<bool>(out_);
    const int err = errno;
    out_.close();
    if (!flushed || !out_) fail(err != 0 ? err : errno);
}

void write_file(const std::filesystem::path& path, std::string_view text, std::string what) {
    OutputFile f(path, std::move(what));
    f.stream().write(text.data(), static_cast<std::streamsize>(text.size()));
    f.close();
}

} // namespace rcsim
