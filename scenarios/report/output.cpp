#include "scenarios/report/output.h"

#include "models/config_error.h"
#include "models/output_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>

namespace rcsim {

void prepare_out_dir(const std::string& dir) {
    if (dir.empty()) return;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
        throw ConfigError("--out '" + dir + "': cannot create the output directory" + (ec ? ": " + ec.message() : ""));
}

void write_report_json(const std::filesystem::path& dir, const nlohmann::json& report) {
    write_file(dir / "report.json", report.dump(2) + "\n", "the report");
}

sc_core::sc_trace_file* open_vcd(const std::string& path) {
    const std::string ext = ".vcd";
    const bool has_ext = path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
    const std::string stem = has_ext ? path.substr(0, path.size() - ext.size()) : path;
    // SystemC's VCD writer ignores write errors, so try one write here: a path on a full disk or
    // /dev/full fails now, not silently after the run.
    std::ofstream probe(stem + ext);
    probe << "$comment rcsim $end\n" << std::flush;
    if (!probe) throw ConfigError(stem + ext, 0, std::string("cannot write the VCD file: ") + std::strerror(errno));
    return sc_core::sc_create_vcd_trace_file(stem.c_str());
}

} // namespace rcsim
