// Fuzz target: the numeric CSV reader (dem::read_numeric_csv) of [[sphere_files]] and the bench
// scenes' grain and foil files, with and without a header asked for.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dem/io/csv.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = fuzz::write_file("numbers.csv", fuzz::as_text(data, size));
    fuzz::expect_only_reader_errors([&] { dem::read_numeric_csv(path, 4); }, path);
    fuzz::expect_only_reader_errors(
        [&] {
            std::vector<std::string> header;
            dem::read_numeric_csv(path, 2, &header);
        },
        path);
    return 0;
}
