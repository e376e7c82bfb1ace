// Fuzz target: a measured loop for `vppdem calibrate --experiment` (vpp::read_experiment), with
// the checks calibrate makes before any simulation (vpp::check_experiment_orientation) and the
// misfit of the loop against itself (vpp::loop_misfit: the cycle split, the branches, the
// interpolation on the measured samples). The same reader (vpp::read_loop_csv) takes the
// forces.csv of `vppdem analyze`.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "vpp/calibration/calibrate.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = fuzz::write_file("experiment.csv", fuzz::as_text(data, size));
    // The format's flags from the first byte, so both sign conventions and units are reached.
    vpp::ExperimentFormat f;
    const uint8_t flags = size ? data[0] : 0;
    f.compression_negative = flags & 1;
    if (flags & 2) f.disp_scale = 1e-3;
    if (flags & 4) f.force_scale = 1e3;
    fuzz::expect_only_reader_errors(
        [&] {
            const vpp::LoopSeries s = vpp::read_experiment(path, f);
            vpp::check_experiment_orientation(s, path, f.compression_negative, (flags & 8) == 0);
        },
        path);
    // The misfit's refusals ("no complete cycle to compare", "a cycle has no loading branch")
    // name no file: calibrate adds the case.
    fuzz::expect_only_reader_errors([&] {
        const vpp::LoopSeries s = vpp::read_experiment(path, f);
        vpp::loop_misfit(s, s, 8);
    });
    return 0;
}
