"""What a sweep refuses before any work, and how it names it: the values as typed, what
differs from the study already in the folder."""

from conftest import run_cli


def test_an_lhs_range_is_judged_at_its_ends_as_typed(capsys, tmp_path):
    """A range reaching a negative mass was taken or refused as --n and --seed fell (the
    points drawn inside it were judged), naming a value no one typed (-0.10782)."""
    for rng, n in (("-10:1000", 3), ("-10:100", 3), ("-10:100", 5)):
        code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "--design", "lhs", "--n", n,
                               "-p", f"X.mechanics.M_t={rng}", "-o", tmp_path / "o",
                               "--workers", 1)
        assert code == 2, (rng, n)
        assert "X.mechanics.M_t = -10:" in " ".join(err.split()), err
    assert not (tmp_path / "o").exists()
