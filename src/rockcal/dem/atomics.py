"""Atomic operations for compiled code: what the engines' threads share the tasks of their steps
by (`tasks`).

numba offers no atomic operations on the CPU, so these are LLVM's own (`atomicrmw`, `cmpxchg`,
`load atomic`), emitted through `numba.extending.intrinsic`, on an element of an int64 array.
Each is sequentially consistent: what a thread wrote before it changed a counter is seen by
every thread that has read the change.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


def _element_pointer(context, builder, array_type, array, index):
    view = context.make_array(array_type)(context, builder, array)
    return cgutils.get_item_pointer(context, builder, array_type, view, [index])


@intrinsic
def fetch_add(typingctx, array, index, value):
    """array[index] += value, atomically; the value before."""
    def codegen(context, builder, signature, args):
        pointer = _element_pointer(context, builder, signature.args[0], args[0], args[1])
        return builder.atomic_rmw("add", pointer, args[2], "seq_cst")
    return types.int64(array, index, value), codegen


@intrinsic
def compare_exchange(typingctx, array, index, expected, value):
    """array[index] = value if it is `expected`, atomically; whether it was."""
    def codegen(context, builder, signature, args):
        pointer = _element_pointer(context, builder, signature.args[0], args[0], args[1])
        expected, value = (context.cast(builder, v, t, types.int64)
                           for v, t in zip(args[2:], signature.args[2:]))
        outcome = builder.cmpxchg(pointer, expected, value, "seq_cst", "seq_cst")
        return builder.extract_value(outcome, 1)
    return types.boolean(array, index, expected, value), codegen


@intrinsic
def load(typingctx, array, index):
    """array[index], read atomically (never kept in a register across a waiting loop)."""
    def codegen(context, builder, signature, args):
        pointer = _element_pointer(context, builder, signature.args[0], args[0], args[1])
        return builder.load_atomic(pointer, "seq_cst", 8)
    return types.int64(array, index), codegen


@intrinsic
def yield_core(typingctx):
    """The C library's sched_yield(): let another thread have this core."""
    def codegen(context, builder, signature, args):
        function = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.IntType(32), []), "sched_yield")
        return builder.call(function, [])
    return types.int32(), codegen
