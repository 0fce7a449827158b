// The coarse-graining kernels a scene may name (coarse.method): one line each. A kernel is
// defined in coarse/kernels/<name>.cpp as a `const KernelShape <name>_kernel`.
#include "coarse/kernel.h"

namespace pilelab::coarse {

#define PILELAB_KERNELS(X) \
  X(gaussian)              \
  X(lucy)                  \
  X(heaviside)             \
  X(linear)

#define PILELAB_DECLARE_KERNEL(name) extern const KernelShape name##_kernel;
PILELAB_KERNELS(PILELAB_DECLARE_KERNEL)
#undef PILELAB_DECLARE_KERNEL

const std::vector<const KernelShape*>& kernel_shapes() {
#define PILELAB_LIST_KERNEL(name) &name##_kernel,
  static const std::vector<const KernelShape*> shapes = {PILELAB_KERNELS(PILELAB_LIST_KERNEL)};
#undef PILELAB_LIST_KERNEL
  return shapes;
}

}  // namespace pilelab::coarse
