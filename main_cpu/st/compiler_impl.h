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
/// An integer or real literal that still takes the type its use needs.
bool untyped(const Expr& e);

class Compiler {
public:
    explicit Compiler(Unit& u) : u_(u) {}

    void add_source(const std::string& text, const std::string& file);
    void finish();

private:
    struct Found {
        const VarInfo* var = nullptr;
        bool global = false;
    };
    struct Decl {
        std::unique_ptr<ParseNode> root_keep; // the tree of the file, held by its first POU
        const ParseNode* node = nullptr;
        PouType* pou = nullptr;
        std::string_view file;
        enum class State { declared, laying_out, laid_out, compiling, compiled } state = State::declared;
    };

    /// A TYPE ... END_TYPE declaration, defined when first used (types may refer to later ones).
    struct TypeDecl {
        const ParseNode* node = nullptr;
        std::string_view file;
        enum class State { declared, defining, defined } state = State::declared;
        Type type;
    };

    Unit& u_;
    std::vector<std::unique_ptr<ParseNode>> trees_;
    std::map<std::string, TypeDecl> type_decls_;
    std::map<std::string, Decl> decls_;
    std::vector<std::pair<const ParseNode*, std::string_view>> global_blocks_;
    std::string_view file_;    // of the node being compiled
    PouType* cur_ = nullptr;   // the POU whose body is being compiled
    int loops_ = 0;
    bool constants_only_ = false; // compiling an initial value: only constants may be named

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
    Type define_type(TypeDecl& d, const std::string& name);
    Type define_enum(const ParseNode& spec, const std::string& name, const ParseNode* init);
    Type define_struct(const ParseNode& spec, const std::string& name);
    std::vector<Value> default_values(const Type& t);
    void init_into(std::vector<Value>& out, std::size_t at, const Type& t, const ParseNode& value,
                   const std::string& name);
    void add_vars(PouType& p, const ParseNode& block, PouType::Pou where);
    void add_var(PouType& p, const std::string& name, const ParseNode& at_node, Type t, VarKind kind,
                 const ParseNode* init);
    std::vector<Value> initial_values(const Type& t, const ParseNode& init, const std::string& name, PouType* scope);
    /// The initial inputs of an FB instance `(PT := T#1s)` or of each of an ARRAY OF one
    /// `[(PT := T#1s), (PT := T#2s)]`: per instance, all its value slots (none: the defaults).
    std::vector<std::vector<Value>> fb_initial_values(const Type& t, const ParseNode& init, const std::string& name,
                                                      PouType* scope);
    std::vector<Value> fb_inputs(const PouType& fb, const ParseNode& value, const std::string& name);

    // expressions
    ExprPtr expr(const ParseNode& n);
    ExprPtr literal(const ParseNode& n);
    ExprPtr typed_literal(const ParseNode& n);
    ExprPtr string_literal(const ParseNode& n);
    /// A name that stands for a value: a VAR CONSTANT or an enumeration value (nullptr if neither).
    ExprPtr named_constant(const ParseNode& ident_node);
    /// An expression where a whole STRUCT, ARRAY or STRING variable may stand (assignments, inputs).
    ExprPtr value_expr(const ParseNode& n);
    ExprPtr shift(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n);
    ExprPtr select(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n);
    ExprPtr string_call(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n);
    ExprPtr binary_chain(const ParseNode& n);
    ExprPtr binary(Op op, const std::string& sym, ExprPtr a, ExprPtr b, const ParseNode& at_node);
    ExprPtr unary(const ParseNode& n);
    ExprPtr call(const ParseNode& n);
    ExprPtr builtin(const std::string& name, std::vector<ExprPtr> args, const ParseNode& n);
    /// The one type all of args[from..] convert to (MIN, MAX, LIMIT, SEL, MUX).
    Type common_of(const std::vector<ExprPtr>& args, std::size_t from, const std::string& name, const ParseNode& n);
    ExprPtr conversion(Kind from, Kind to, std::vector<ExprPtr> args, const ParseNode& n, bool truncate);
    LValuePtr variable(const ParseNode& n, bool for_write, bool whole = false);
    LValuePtr place(const Found& f, const ParseNode& id);
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
    std::int64_t case_label(const ParseNode& n, const Type& selector);
    /// Binds a call's `name := variable` to a VAR_IN_OUT (the same type, a variable).
    LValuePtr in_out_argument(const VarInfo& v, const ParseNode& value, const std::string& pou);
    ExprPtr condition(const ParseNode& n, const char* what);

    Found lookup(const ParseNode& ident_node);
    Found try_lookup(const std::string& upper_name) const;
    static std::string name_of(const ParseNode& n) { return n.string(); }
};

} // namespace rcsim::st::detail
