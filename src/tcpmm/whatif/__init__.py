"""What-if tools: how a prediction changes when the model or the servo settings do.

A spread runs a circle on machines drawn from the identified uncertainty
(:mod:`~tcpmm.whatif.spread`); a sweep runs a model and program over a design of named
parameters (:mod:`~tcpmm.whatif.sweep`); tuning proposes servo gains and predicts the path
before and after (:mod:`~tcpmm.whatif.tuning`).
"""
