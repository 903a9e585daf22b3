"""``tcpmm simulate --controller``: the controller-side compensation applied to a run as the
drives apply it."""

from __future__ import annotations

CONTROLLER_HELP = ("PARAMS.yaml: the controller-side compensation (tcpmm compensate "
                    "--controller-out) applied as the drives apply it: the friction pulse "
                    "added to the current command at each reversal, the cross-talk "
                    "feed-forward to the position setpoint.")


def as_the_drives_take_it(cmd, controller, machine):
    """The command and the current pulses per axis the drives get with the controller-side
    parameters of ``--controller`` (the command alone, no pulses, without) [m, A]; an axis of
    the command the file leaves out is said."""
    if controller is None:
        return cmd, None
    from ..compensate.controller_file import read_controller_parameters
    from ..compensate.drive import drive_inputs
    from ..io.modelfile import model_identity

    params = read_controller_parameters(controller, machine.axes, model_identity(machine))
    bare = [a for a in cmd.axes if a in machine.axes and a not in params]
    if bare:  # an axis the file leaves out runs as without compensation: say which
        import warnings

        from ..errors import InputWarning

        warnings.warn(f"{controller} has no parameters for {', '.join(bare)}: "
                      f"{'it runs' if len(bare) == 1 else 'they run'} without "
                      "controller-side compensation", InputWarning, stacklevel=2)
    ctc, pulses = drive_inputs(cmd, {a: p for a, p in params.items() if a in cmd.axes})
    return ctc, pulses or None
