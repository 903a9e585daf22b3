"""Machines that need no measurement: the built-in demonstration machine
(:mod:`~tcpmm.machines.builtin`) and the virtual one, which records what a model's
sensors would (:mod:`~tcpmm.machines.virtual`); and the paper's circular test
(:mod:`~tcpmm.machines.paper`)."""
