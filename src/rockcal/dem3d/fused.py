"""Fused multiply-add, a × b + c rounded once, for the compiled 3D laws.

IEEE 754 defines the fused multiply-add exactly, so it gives the same bits on every processor:
LLVM emits the processor's FMA instruction (one instruction where a product and a sum take
two, in vector loops too) or, on a processor without one, a correctly rounded library call.
numba fuses nothing itself unless fast-math allows it, and then the compiler, and with it the
processor, would choose where: the laws say where instead.
"""

from numba import types
from numba.extending import intrinsic


@intrinsic
def fma(typingctx, a, b, c):
    """a × b + c with one rounding, in compiled code."""
    signature = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, sig, args):  # numba casts the arguments to floats first
        return builder.fma(*args)

    return signature, codegen
