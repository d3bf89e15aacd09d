"""The bonded pairs' phase of a step, whatever their law: `add_bonded_forces` runs the force
loop of the bonded-pair state it is given (parallel bonds' `laws.Bonds`, flat joints'
`flatjoint.FlatJoints`, a new law's own). Each law registers its loop for its state's type
with `bond_phase`; numba picks the loop by that type when it compiles the engine, so the engine
holds no branch on the material and caches one specialisation per material.

A loop takes (first, last, disks, pi, pj, contact_shear, bonded, law, dt, loads, into_rows):
it adds the forces and moments of bonded pairs first..last-1 (grains pi[p], pj[p], rows of
`disks`) to `loads`, or into rows of their own (`laws.pair_rows`), with the pairs' contact
shear forces and the law constants (`laws.Laws`) if its law needs them.
"""

from numba.extending import overload


def add_bonded_forces(first, last, disks, pi, pj, contact_shear, bonded, law, dt, loads,
                      into_rows=-1):
    """The force loop registered for `bonded`'s type (in compiled code only)."""
    raise NotImplementedError("add_bonded_forces runs in compiled code only")


def bond_phase(state_type: type):
    """Register the decorated compiled loop as `add_bonded_forces` for states of `state_type`."""
    def register(loop):
        @overload(add_bonded_forces)
        def _of_type(first, last, disks, pi, pj, contact_shear, bonded, law, dt, loads,
                     into_rows=-1):
            if getattr(bonded, "instance_class", None) is state_type:
                return lambda first, last, disks, pi, pj, contact_shear, bonded, law, dt, loads, \
                    into_rows=-1: loop(first, last, disks, pi, pj, contact_shear, bonded, law, dt,
                                       loads, into_rows)
        return loop
    return register
