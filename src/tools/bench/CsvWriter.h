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
      else line << std::get<std::string>(cells[k]);
    }
    out_ << line.str() << '\n';
    out_.flush();
    if (!out_) throw std::runtime_error(path_ + ": write failed");
  }

 private:
  std::string path_;
  std::ofstream out_;
};

}  // namespace pbf_bench
