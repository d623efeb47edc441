#include "tests/support/csv_table.h"

#include <fstream>
#include <sstream>

namespace penumbra::test {

CsvTable readCsvTable(const std::string& path) {
    CsvTable table;
    std::ifstream in(path);
    std::getline(in, table.header);
    for (std::string line; std::getline(in, line);) {
        std::vector<double> row;
        std::stringstream fields(line);
        for (std::string field; std::getline(fields, field, ',');)
            row.push_back(std::stod(field));
        table.rows.push_back(std::move(row));
    }
    return table;
}

}  // namespace penumbra::test
