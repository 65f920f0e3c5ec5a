#include "scenarios/report/output.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>

namespace rcsim {

const std::vector<std::string>& run_file_names() {
    static const std::vector<std::string> names = {
        "report.json",    "report.html",    "interrupts.csv",      "interrupts.csv.gz",    "profile.txt",
        "profile.folded", "trajectory.csv", "trajectory.svg",      "trajectory_time.svg", "trajectory_pulses.csv", "bound.json"};
    // (symbols.elf is written by --gdb before the run starts: it is always the run's own.)
    return names;
}

void prepare_out_dir(const std::string& dir) {
    if (dir.empty()) return;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
        throw ConfigError("--out '" + dir + "': cannot create the output directory" + (ec ? ": " + ec.message() : ""));
    for (const std::string& name : run_file_names()) {
        const std::filesystem::path f = std::filesystem::path(dir) / name;
        if (!std::filesystem::is_regular_file(f, ec)) continue;
        if (!std::filesystem::remove(f, ec) || ec)
            throw ConfigError(f.string(), 0, "cannot remove the earlier run's file" + (ec ? ": " + ec.message() : ""));
    }
}

void prepare_output_folders(const std::vector<std::string*>& files) {
    for (const std::string* f : files) {
        const std::filesystem::path parent = std::filesystem::path(*f).parent_path();
        if (parent.empty()) continue;
        std::error_code ec;
        std::filesystem::create_directories(parent, ec);
        if (ec || !std::filesystem::is_directory(parent))
            throw ConfigError(*f, 0, "cannot create its folder" + (ec ? ": " + ec.message() : ""));
    }
}

void write_report_json(const std::filesystem::path& dir, const nlohmann::json& report) {
    write_file(dir / "report.json", report.dump(2) + "\n", "the report");
}

bool is_vcd_name(const std::string& path) {
    const std::string ext = ".vcd";
    return path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
}

sc_core::sc_trace_file* open_vcd(const std::string& path) {
    const std::string ext = ".vcd";
    const std::string stem = is_vcd_name(path) ? path.substr(0, path.size() - ext.size()) : path;
    // SystemC's VCD writer ignores write errors, so try one write here: a path on a full disk or
    // /dev/full fails now, not silently after the run.
    std::ofstream probe(stem + ext);
    probe << "$comment rcsim $end\n" << std::flush;
    if (!probe) throw ConfigError(stem + ext, 0, std::string("cannot write the VCD file: ") + std::strerror(errno));
    return sc_core::sc_create_vcd_trace_file(stem.c_str());
}

} // namespace rcsim
