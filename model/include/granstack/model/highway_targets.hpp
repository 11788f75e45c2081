// Which instruction sets granstack's Google Highway kernels are compiled for, included by each
// kernel's file after it names itself (HWY_TARGET_INCLUDE), in place of hwy/foreach_target.h and
// hwy/highway.h: every one Highway targets but the scalable vectors (SVE, RISC-V V), which cannot
// be held in arrays and structures nor kept to a kernel's lanes; an ARM CPU with SVE runs the NEON
// kernels. No include guard: foreach_target.h includes the kernel's file again for each
// instruction set, and so this.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
