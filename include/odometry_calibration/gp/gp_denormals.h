// Denormal-safe arithmetic for the GP's prediction loops. Far from the training
// inputs an RBF kernel value exp(-q/2) underflows into the denormal range (q ~ 1416-1490) and
// every product with it costs a microcode assist, about a hundred times a normal multiply: a
// mecanum or coarse-encoder model spent most of its prediction time there. Within a scope of
// DenormalsAsZero the CPU flushes denormal results and operands to zero (x86 MXCSR FTZ and
// DAZ; the previous mode is restored at the end of the scope). A denormal is below 2.3e-308,
// so a prediction changes by less than that in absolute terms. Elsewhere (no SSE) a no-op.
#pragma once

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace odometry_calibration {

/// Flush-to-zero and denormals-are-zero for the current thread while in scope, restored after.
class DenormalsAsZero
{
public:
#if defined(__SSE2__)
  DenormalsAsZero() : saved_(_mm_getcsr())
  {
    _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero);
  }
  ~DenormalsAsZero()
  {
    _mm_setcsr(saved_);
  }
#else
  DenormalsAsZero() = default;
#endif
  DenormalsAsZero(const DenormalsAsZero&) = delete;
  DenormalsAsZero& operator=(const DenormalsAsZero&) = delete;

private:
#if defined(__SSE2__)
  static constexpr unsigned kFlushToZero = 0x8000;       ///< MXCSR bit 15 (FTZ)
  static constexpr unsigned kDenormalsAreZero = 0x0040;  ///< MXCSR bit 6 (DAZ)
  unsigned saved_;
#endif
};

}  // namespace odometry_calibration
