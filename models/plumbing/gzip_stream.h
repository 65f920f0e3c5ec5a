// rcsim — gzip streams over zlib (RFC 1952), so that a long run's row files stay in proportion
// (interrupts.csv.gz, docs/scenarios.md "Output files") and are read back as they were written.
// The writer deflates into another stream (an OutputFile's, which reports write errors); the
// reader takes a gzip file or a plain one alike (zlib passes uncompressed input through).
#pragma once

#include <filesystem>
#include <istream>
#include <memory>
#include <ostream>

namespace rcsim {

/// Deflates everything written to it into `sink` as one gzip member. The header carries no time
/// or name, so the same rows give the same bytes (reports are compared byte for byte).
class GzipWriter : public std::ostream {
public:
    explicit GzipWriter(std::ostream& sink);
    ~GzipWriter() override;
    GzipWriter(const GzipWriter&) = delete;
    GzipWriter& operator=(const GzipWriter&) = delete;
    /// Writes the last compressed bytes and the gzip trailer into the sink. Call once, before
    /// the sink is closed; nothing may be written after it.
    void finish();

private:
    class Buffer;
    std::unique_ptr<Buffer> buffer_;
};

/// Reads a gzip file, or a plain file as it is. A file that cannot be opened reads as empty (the
/// caller decides whether that is an error); a corrupt gzip file ends where its damage starts.
class GzipReader : public std::istream {
public:
    explicit GzipReader(const std::filesystem::path& path);
    ~GzipReader() override;
    GzipReader(const GzipReader&) = delete;
    GzipReader& operator=(const GzipReader&) = delete;

private:
    class Buffer;
    std::unique_ptr<Buffer> buffer_;
};

} // namespace rcsim
