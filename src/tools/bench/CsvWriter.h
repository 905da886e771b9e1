#pragma once
// Minimal CSV output: a header, then rows of numbers and words. Throws when the file
// cannot be written, naming it (a bench that silently writes nothing is worse than none).

#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace pbf_bench {

class CsvWriter {
 public:
  using Cell = std::variant<double, long long, std::string>;

  CsvWriter(const std::string& path, const std::vector<std::string>& header) : path_(path), out_(path) {
    if (!out_) throw std::runtime_error(path + ": cannot write (does the output folder exist?)");
    row(std::vector<Cell>(header.begin(), header.end()));
  }

  void row(const std::vector<Cell>& cells) {
    std::ostringstream line;
    line.precision(7);
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (k) line << ',';
      if (const auto* d = std::get_if<double>(&cells[k])) line << *d;
      else if (const auto* i = std::get_if<long long>(&cells[k])) line << *i;
      else line << quoted(std::get<std::string>(cells[k]));
    }
    out_ << line.str() << '\n';
    out_.flush();
    if (!out_) throw std::runtime_error(path_ + ": write failed");
  }

 private:
  // RFC 4180: words with a comma, quote or newline go in quotes, quotes doubled.
  static std::string quoted(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  }

  std::string path_;
  std::ofstream out_;
};

}  // namespace pbf_bench
