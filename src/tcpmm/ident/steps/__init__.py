"""The steps of identification, one module each, in the order
:mod:`tcpmm.ident.chain` runs them.

Each step is a plain function ``step(run, options)`` of the axis's
:class:`~tcpmm.ident.chain.AxisRun` (the records and what the steps before found) and the
shared :class:`~tcpmm.ident.options.IdentifyOptions`; it returns its result, a small frozen
holder where it has more than one part.
"""
