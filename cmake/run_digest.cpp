// wetdem_run_digest: the text the run version is hashed from (cmake/git_describe.cmake).
//
//   wetdem_run_digest ROOT OUT FILE...
//
// writes to OUT, for each FILE (relative to ROOT, in the order given), a line "== FILE" and the file's tokens
// as the compiler reads them, without what cannot change a run: comments, the layout of whitespace, and where
// a string literal is split into adjacent pieces ("ab" "c" is "abc", C++ [lex.string]/7). A comment edit or a
// clang-format reflow then keeps every stored run; any other change, a token or a string's text, invalidates
// them.
//
// C and GLSL sources (.h .cpp .comp .glsl .in) are normalised; any other file (CMakeLists.txt) is copied as
// is. The normalisation is conservative: where two spellings might differ in meaning, both are kept.
// - Whitespace and comments: a run of them becomes one space, or nothing next to ( ) [ ] { } , ; . (which
//   never join a neighbour into another token). Inside a preprocessor directive it is always one space
//   (`#define F (x)` is not `#define F(x)`), and the directive's end of line is kept.
// - Literals: string and character literals, raw strings and numbers (with ' separators) are copied byte
//   for byte. Adjacent plain string literals are joined, unless the first ends in an escape that could run
//   on (\x, \u, octal) or a literal has a prefix or a suffix.
// Errors (an unreadable file, too few arguments) exit 1 with a message: the build then stops.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace {

bool ident_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

bool digit(char c) {
  return c >= '0' && c <= '9';
}

// Characters next to which a space never separates two tokens that would otherwise join into one.
bool glue(char c) {
  return c == '(' || c == ')' || c == '[' || c == ']' || c == '{' || c == '}' || c == ',' || c == ';' ||
         c == '.';
}

// Could the end of a string literal body (without its closing quote) run on into the next piece's text if the
// two were joined? \x takes any number of hex digits, \u / \U and octal escapes take digits too.
bool escape_may_run_on(const std::string& body) {
  for (size_t i = 0; i + 1 < body.size(); ++i) {
    if (body[i] != '\\') continue;
    const char e = body[i + 1];
    if (e == 'x' || e == 'u' || e == 'U' || (e >= '0' && e <= '7')) return true;
    ++i;  // skip the escaped character (\\ included)
  }
  return false;
}

class Normaliser {
 public:
  explicit Normaliser(const std::string& s) : s_(s) {}

  std::string run() {
    while (i_ < s_.size()) step();
    return out_;
  }

 private:
  const std::string& s_;
  size_t i_ = 0;
  std::string out_;
  bool pending_space_ = false;  // whitespace or a comment seen since the last token
  bool line_start_ = true;      // only whitespace since the last newline of the input
  bool directive_ = false;      // inside a preprocessor directive
  // The most recent plain string literal, while nothing but whitespace and comments follows it: where its
  // closing quote is in out_, and whether the next plain literal may be joined onto it.
  size_t string_open_ = 0;
  size_t string_close_ = std::string::npos;

  char at(size_t k) const { return k < s_.size() ? s_[k] : '\0'; }

  // Before a token's first character c: the pending separator, if one is needed.
  void separate(char c) {
    if (pending_space_ && !out_.empty() && out_.back() != '\n') {
      if (directive_ || !(glue(out_.back()) || glue(c))) out_ += ' ';
    }
    pending_space_ = false;
    line_start_ = false;
  }

  void step() {
    const char c = s_[i_];
    if (c == '\\' && at(i_ + 1) == '\n') {  // line splice: whitespace (a directive goes on)
      i_ += 2;
      pending_space_ = true;
      return;
    }
    if (c == '\n') {
      ++i_;
      line_start_ = true;
      if (directive_) {
        out_ += '\n';
        directive_ = false;
        pending_space_ = false;
        string_close_ = std::string::npos;
      } else {
        pending_space_ = true;
      }
      return;
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++i_;
      pending_space_ = true;
      return;
    }
    if (c == '/' && at(i_ + 1) == '/') {  // to the end of the line (the newline itself is read next)
      while (i_ < s_.size() && s_[i_] != '\n') ++i_;
      pending_space_ = true;
      return;
    }
    if (c == '/' && at(i_ + 1) == '*') {
      const size_t e = s_.find("*/", i_ + 2);
      for (size_t k = i_; k < (e == std::string::npos ? s_.size() : e); ++k)
        if (s_[k] == '\n') line_start_ = true;
      i_ = e == std::string::npos ? s_.size() : e + 2;
      pending_space_ = true;
      return;
    }
    if (c == '#' && line_start_ && !directive_) {
      if (!out_.empty() && out_.back() != '\n') out_ += '\n';
      pending_space_ = false;
      directive_ = true;
      line_start_ = false;
      out_ += c;
      ++i_;
      string_close_ = std::string::npos;
      return;
    }
    if (c == '"') {
      string_literal();
      return;
    }
    if (c == '\'') {
      separate(c);
      copy_quoted('\'');
      string_close_ = std::string::npos;
      return;
    }
    if (digit(c) || (c == '.' && digit(at(i_ + 1)))) {
      if (!(ident_char(c) && !out_.empty() && !pending_space_ && ident_char(out_.back()))) {
        number();
        return;
      }
    }
    separate(c);
    out_ += c;
    ++i_;
    string_close_ = std::string::npos;
  }

  // A pp-number ([lex.ppnumber]): digits, letters, '.', digit separators and an exponent's sign.
  void number() {
    separate(s_[i_]);
    string_close_ = std::string::npos;
    while (i_ < s_.size()) {
      const char c = s_[i_];
      const char p = out_.back();
      const bool sign = (c == '+' || c == '-') && (p == 'e' || p == 'E' || p == 'p' || p == 'P');
      const bool separator = c == '\'' && ident_char(at(i_ + 1));
      if (!(ident_char(c) || c == '.' || sign || separator)) break;
      out_ += c;
      ++i_;
    }
  }

  // Copies a quoted literal from its opening quote to its closing one, escapes included.
  void copy_quoted(char q) {
    out_ += s_[i_++];
    while (i_ < s_.size()) {
      const char c = s_[i_];
      out_ += c;
      ++i_;
      if (c == '\\' && i_ < s_.size()) {
        out_ += s_[i_++];
        continue;
      }
      if (c == q || c == '\n') return;  // a newline ends an unterminated literal (as a compiler reports it)
    }
  }

  void string_literal() {
    const bool prefixed = !pending_space_ && !out_.empty() && ident_char(out_.back());
    if (prefixed) {
      // The identifier just written is the prefix; R in it makes a raw string ([lex.string]).
      size_t b = out_.size();
      while (b > 0 && ident_char(out_[b - 1])) --b;
      const std::string prefix = out_.substr(b);
      if (prefix == "R" || prefix == "u8R" || prefix == "uR" || prefix == "UR" || prefix == "LR") {
        raw_string();
      } else {
        copy_quoted('"');
      }
      string_close_ = std::string::npos;
      return;
    }
    if (string_close_ != std::string::npos &&
        !escape_may_run_on(out_.substr(string_open_ + 1, string_close_ - string_open_ - 1))) {
      // Join onto the previous piece: drop its closing quote and this opening one.
      out_.erase(string_close_);
      pending_space_ = false;
      const size_t start = out_.size();
      copy_quoted('"');
      out_.erase(start, 1);
      close_plain_literal(string_open_);
      return;
    }
    separate('"');
    const size_t open = out_.size();
    copy_quoted('"');
    close_plain_literal(open);
  }

  // After a plain literal whose opening quote is at `open` in out_: joinable unless a suffix follows at once
  // ("..."_s) or it was not closed.
  void close_plain_literal(size_t open) {
    const bool closed = out_.size() > open + 1 && out_.back() == '"';
    string_open_ = open;
    string_close_ = (closed && !ident_char(at(i_))) ? out_.size() - 1 : std::string::npos;
  }

  // R"delim( ... )delim": copied to the closing delimiter, whatever it holds.
  void raw_string() {
    const size_t open = s_.find('(', i_);
    if (open == std::string::npos) {  // malformed: copy the rest
      out_ += s_.substr(i_);
      i_ = s_.size();
      return;
    }
    const std::string close = ")" + s_.substr(i_ + 1, open - i_ - 1) + "\"";
    const size_t e = s_.find(close, open);
    const size_t end = e == std::string::npos ? s_.size() : e + close.size();
    out_ += s_.substr(i_, end - i_);
    i_ = end;
  }
};

bool c_like(const std::string& path) {
  for (const char* ext : {".h", ".cpp", ".comp", ".glsl", ".in"}) {
    const std::string e(ext);
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0) return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: wetdem_run_digest ROOT OUT FILE...\n";
    return 1;
  }
  const std::string root = argv[1];
  std::ostringstream all;
  for (int a = 3; a < argc; ++a) {
    const std::string rel = argv[a];
    std::ifstream in(root + "/" + rel, std::ios::binary);
    if (!in) {
      std::cerr << "wetdem_run_digest: cannot read " << root << "/" << rel << "\n";
      return 1;
    }
    std::ostringstream text;
    text << in.rdbuf();
    all << "== " << rel << "\n" << (c_like(rel) ? Normaliser(text.str()).run() : text.str()) << "\n";
  }
  // Written only when it changes, so the build's timestamps stay put for an unchanged tree.
  const std::string out_path = argv[2];
  std::ifstream old(out_path, std::ios::binary);
  std::ostringstream before;
  if (old) before << old.rdbuf();
  if (before.str() != all.str()) {
    std::ofstream out(out_path, std::ios::binary | std::ios::trunc);
    out << all.str();
    if (!out) {
      std::cerr << "wetdem_run_digest: cannot write " << out_path << "\n";
      return 1;
    }
  }
  return 0;
}
