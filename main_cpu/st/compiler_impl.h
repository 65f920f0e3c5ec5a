// rcsim — the Structured Text compiler's internals, shared by compiler.cpp (declarations),
// compile_expr.cpp (expressions, types) and compile_stmt.cpp (statements). See compiler.h.
#pragma once

#include "main_cpu/st/compiler.h"
#include "main_cpu/st/parser.h"

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace rcsim::st::detail {

std::string trim(std::string s);
std::string strip_underscores(std::string s);
/// IEC 61131-3 3rd ed. Figure 11: the implicit conversions that lose nothing.
bool widens(Kind from, Kind to);
/// Whether an integer value is in the range of `k`.
bool fits(Kind k, std::int64_t v);
const std::map<std::string, Kind>& elementary_types();

class Compiler {
public:
    explicit Compiler(Unit& u) : u_(u) {}

    void add_source(const std::string& text, const std::string& file);
    void finish();

private:
    struct Decl {
        std::unique_ptr<ParseNode> root_keep; // the tree of the file, held by its first POU
        const ParseNode* node = nullptr;
        PouType* pou = nullptr;
        std::string_view file;
        enum class State { declared, laying_out, laid_out, compiling, compiled } state = State::declared;
    };

    Unit& u_;
    std::vector<std::unique_ptr<ParseNode>> trees_;
    std::map<std::string, Decl> decls_;
    std::vector<std::pair<const ParseNode*, std::string_view>> global_blocks_;
    std::string_view file_;    // of the node being compiled
    PouType* cur_ = nullptr;   // the POU whose body is being compiled
    int loops_ = 0;

    SourcePos at(const ParseNode& n) const { return SourcePos{file_, n.begin().line, n.begin().column}; }
    [[noreturn]] void fail(const ParseNode& n, const std::string& what) const {
        throw CompileError(at(n).str() + ": " + what);
    }

    // declarations
    void declare(const ParseNode& root, std::string_view file);
    void layout(Decl& d);
    void compile_body(Decl& d);
    Decl* find_decl(const std::string& upper_name);
    Type resolve_type(const ParseNode& n);
    void add_vars(PouType& p, const ParseNode& block, PouType::Pou where);
    void add_var(PouType& p, const std::string& name, const ParseNode& at_node, Type t, VarKind kind,
                 const ParseNode* init);
    std::vector<Value> initial_values(const Type& t, const ParseNode& init, const std::string& name);

    // expressions
    ExprPtr expr(const ParseNode& n);
    ExprPtr literal(const ParseNode& n);
    ExprPtr binary_chain(const ParseNode& n);
    ExprPtr binary(Op op, const std::string& sym, ExprPtr a, ExprPtr b, const ParseNode& at_node);
    ExprPtr unary(const ParseNode& n);
    ExprPtr call(const ParseNode& n);
    ExprPtr builtin(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n);
    ExprPtr conversion(Kind from, Kind to, std::vector<ExprPtr> args, const ParseNode& n, bool truncate);
    LValuePtr variable(const ParseNode& n, bool for_write);
    ExprPtr coerce(ExprPtr e, const Type& to, const std::string& what);
    ExprPtr fold(ExprPtr e);
    Type common_type(const Expr& a, const Expr& b, const std::string& sym, const ParseNode& at_node);
    std::int64_t integer_literal(const std::string& text, const ParseNode& n);
    std::int64_t time_literal(const std::string& text, const ParseNode& n);

    // statements
    Block statements(const ParseNode& n);
    StmtPtr statement(const ParseNode& n);
    StmtPtr assignment(const ParseNode& n);
    StmtPtr fb_call(const ParseNode& n);
    StmtPtr if_stmt(const ParseNode& n);
    StmtPtr case_stmt(const ParseNode& n);
    StmtPtr for_stmt(const ParseNode& n);
    ExprPtr condition(const ParseNode& n, const char* what);

    struct Found {
        const VarInfo* var = nullptr;
        bool global = false;
    };
    Found lookup(const ParseNode& ident_node);
    static std::string name_of(const ParseNode& n) { return n.string(); }
};

} // namespace rcsim::st::detail
