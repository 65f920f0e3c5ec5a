// rcsim — gzip streams over zlib. See gzip_stream.h.
#include "models/plumbing/gzip_stream.h"

#include <zlib.h>

#include <array>
#include <stdexcept>

namespace rcsim {

namespace {
constexpr std::size_t kChunk = 64 * 1024;
constexpr int kGzipWindow = 15 + 16; // deflateInit2/inflateInit2: a 32 KB window, gzip wrapper
} // namespace

// Collects what is written in `in_`, deflates it a chunk at a time into the sink.
class GzipWriter::Buffer : public std::streambuf {
public:
    explicit Buffer(std::ostream& sink) : sink_(sink) {
        if (deflateInit2(&z_, Z_DEFAULT_COMPRESSION, Z_DEFLATED, kGzipWindow, 8, Z_DEFAULT_STRATEGY) != Z_OK)
            throw std::runtime_error("zlib: deflateInit2 failed");
        setp(in_.data(), in_.data() + in_.size());
    }
    ~Buffer() override { deflateEnd(&z_); }

    void finish() {
        deflate_pending(Z_FINISH);
        setp(nullptr, nullptr); // nothing more goes in
    }

protected:
    int_type overflow(int_type c) override {
        deflate_pending(Z_NO_FLUSH);
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        *pptr() = traits_type::to_char_type(c);
        pbump(1);
        return c;
    }

private:
    // Deflates in_[0, pptr()) into the sink; with Z_FINISH also the trailer.
    void deflate_pending(int flush) {
        z_.next_in = reinterpret_cast<Bytef*>(pbase());
        z_.avail_in = static_cast<uInt>(pptr() - pbase());
        int rc = Z_OK;
        do {
            z_.next_out = out_.data();
            z_.avail_out = static_cast<uInt>(out_.size());
            rc = deflate(&z_, flush);
            sink_.write(reinterpret_cast<const char*>(out_.data()),
                        static_cast<std::streamsize>(out_.size() - z_.avail_out));
        } while (z_.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
        setp(in_.data(), in_.data() + in_.size());
    }

    std::ostream& sink_;
    z_stream z_{};
    std::array<char, kChunk> in_{};
    std::array<Bytef, kChunk> out_{};
};

GzipWriter::GzipWriter(std::ostream& sink) : std::ostream(nullptr), buffer_(std::make_unique<Buffer>(sink)) {
    rdbuf(buffer_.get());
}

GzipWriter::~GzipWriter() = default;

void GzipWriter::finish() { buffer_->finish(); }

// zlib's gzFile reads gzip and passes plain files through: one buffer over it.
class GzipReader::Buffer : public std::streambuf {
public:
    explicit Buffer(const std::filesystem::path& path) : file_(gzopen(path.c_str(), "rb")) {
        if (file_) gzbuffer(file_, kChunk);
    }
    ~Buffer() override {
        if (file_) gzclose(file_);
    }

protected:
    int_type underflow() override {
        if (!file_) return traits_type::eof();
        const int n = gzread(file_, in_.data(), static_cast<unsigned>(in_.size()));
        if (n <= 0) return traits_type::eof();
        setg(in_.data(), in_.data(), in_.data() + n);
        return traits_type::to_int_type(in_[0]);
    }

private:
    gzFile file_;
    std::array<char, kChunk> in_{};
};

GzipReader::GzipReader(const std::filesystem::path& path)
    : std::istream(nullptr), buffer_(std::make_unique<Buffer>(path)) {
    rdbuf(buffer_.get());
}

GzipReader::~GzipReader() = default;

} // namespace rcsim
