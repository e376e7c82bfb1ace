// The CUDA device where this vppdem was built without it (-DVPPDEM_CUDA=OFF, the default):
// asking for it is refused, naming the option (docs/gpu.md).
#include <stdexcept>

#include "dem/batch/device_api.h"

namespace dem::batch::dev {

std::unique_ptr<Device> cuda_device() {
    throw std::runtime_error(
        "this vppdem was built without CUDA: configure with -DVPPDEM_CUDA=ON (and nvcc, e.g. "
        "-DVPPDEM_NVCC=/usr/local/cuda/bin/nvcc) to run the batch engine on a GPU (docs/gpu.md)");
}
bool cuda_built() { return false; }
int cuda_devices(const char** why) {
    if (why) *why = "built without CUDA (-DVPPDEM_CUDA=OFF)";
    return 0;
}

}  // namespace dem::batch::dev
