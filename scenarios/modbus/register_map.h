// rcsim — the Modbus TCP register map (docs/monitor.md "Modbus TCP"): ONE table in code from which
// the server's tables are sized and filled and `rcsim modbus-map` prints its CSV.
//
// Conventions (the CSV's columns): a 32-bit value takes two registers, the high word at the lower
// address ("big-endian word order", as most PLCs and HMIs default to); `scale` is what the value
// in `unit` is multiplied by to give the register (value = register / scale); a figure with no
// samples yet reads as the type's "not measured" value (kNotMeasured16/32, i32: 0x80000000).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace rcsim::monitor {
class BoardMonitor;
}

namespace rcsim::modbus {

enum class Table : std::uint8_t { coil, discrete_input, input_register, holding_register };
enum class Type : std::uint8_t { bit, u16, i16, u32, i32 };
enum class Access : std::uint8_t { read, read_write };
/// An entry stands once, or once per serial port or per axis (`stride` addresses apart).
enum class Repeat : std::uint8_t { once, per_port, per_axis };

/// --modbus's port when none is given: 502 is Modbus's, and binding it needs root.
constexpr unsigned kDefaultPort = 1502;

constexpr std::uint16_t kNotMeasured16 = 0xFFFF;
constexpr std::uint32_t kNotMeasured32 = 0xFFFFFFFF;
constexpr std::uint32_t kNotMeasuredI32 = 0x80000000;

/// The value of a read-only entry for port/axis `index` (0 for `once`), in the entry's unit;
/// NaN = not measured. Called on the simulation thread between two slices.
using Getter = double (*)(monitor::BoardMonitor& mon, unsigned index);

struct Entry {
    const char* name;        // "{n}" is the port or axis number
    Table table;
    std::uint16_t address;   // of port/axis 0
    Repeat repeat;
    std::uint16_t stride;
    Type type;
    double scale;
    const char* unit;
    Access access;
    const char* description;
    Getter value;            // null for what the server keeps itself (writable cells, the mailbox)
};

/// One address of the map, expanded: what the CSV prints per line.
struct Row {
    std::string name;
    const Entry* entry;
    unsigned index;          // port or axis, 0 for `once`
    std::uint16_t address;
};

const std::vector<Entry>& register_map();
/// Every row, in table then address order.
std::vector<Row> map_rows();
unsigned words(Type t);
const char* to_string(Table t);
const char* to_string(Type t);
/// The size of each table: one past its highest address.
std::uint16_t table_size(Table t);
/// The address of a named entry (of port/axis 0 for a repeated one: "axis{n}.servo_on").
std::uint16_t address_of(const char* name);

/// Whether a client may write `value` to a writable cell (mailbox.count 0..8, step_ms 1..60000).
bool accepts(Table t, std::uint16_t address, std::uint16_t value);

/// `rcsim modbus-map`: name,table,address,type,words,scale,unit,access,description.
void write_map_csv(std::ostream& out);

/// The registers of a value as the map's type and scale hold it (1 or 2 words, high word first).
std::vector<std::uint16_t> encode(Type t, double scale, double value);

} // namespace rcsim::modbus
