// Reading the CSV files `penumbra illuminance` writes: a header line, then rows of numbers.
#pragma once

#include <string>
#include <vector>

namespace penumbra::test {

struct CsvTable {
    std::string header;                     // the first line as written
    std::vector<std::vector<double>> rows;  // each later line's comma-separated numbers
};

// Reads `path`; a missing file gives an empty table (the caller's size checks then fail).
CsvTable readCsvTable(const std::string& path);

}  // namespace penumbra::test
