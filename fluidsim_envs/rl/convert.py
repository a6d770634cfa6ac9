"""Turn the SB3 pickles of a run folder or zoo entry (what versions before the safetensors
format wrote) into files of numbers, once, for folders whose source you trust.

    python -m fluidsim_envs.rl.convert FOLDER [FOLDER ...] --allow-pickle [--policy-only]
                                       [--remove]

Each pickled file is loaded with SB3 (which runs whatever code it carries: hence the flag
that must be given) and written beside it in :mod:`.saved`'s format: the final model and its
statistics (``model.zip``, ``vecnormalize.pkl``, ``replay_buffer.pkl``), the best model
(``best/``) and every checkpoint. A file already converted is left as it is.
``--policy-only`` keeps the final model's policy weights alone (a zoo entry); ``--remove``
deletes each pickle once its conversion is written. From then on every command reads the
folder without ``--allow-pickle``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import files, saved
from .config import ConfigError, load_config
from .files import RunError
from .runs import (
    MODEL,
    PICKLED,
    PICKLED_BEST,
    REPLAY,
    STATS,
    BestModel,
    checkpoint_paths,
    checkpoints,
    final_paths,
)


def pickled_pairs(folder: Path) -> list[tuple[Path, Path, str]]:
    """(pickle, its conversion, kind) of each SB3 file in ``folder``."""
    final, best = final_paths(folder, 0), folder / "best"
    pairs = [
        (folder / PICKLED[MODEL], final.model, "model"),
        (folder / PICKLED[STATS], final.stats, "statistics"),
        (folder / PICKLED[REPLAY], final.replay, "replay"),
        (best / PICKLED_BEST, best / BestModel.MODEL, "model"),
        (best / PICKLED[STATS], best / BestModel.STATS, "statistics"),
    ]
    for steps, old_model in checkpoints(folder, ".zip"):
        new = checkpoint_paths(folder, steps)
        pairs += [
            (old_model, new.model, "model"),
            (old_model.with_name(f"model_vecnormalize_{steps}_steps.pkl"), new.stats, "statistics"),
            (old_model.with_name(f"model_replay_buffer_{steps}_steps.pkl"), new.replay, "replay"),
        ]
    return [(old, new, kind) for old, new, kind in pairs if old.is_file()]


def convert(
    folder: Path, *, allow_pickle: bool, policy_only: bool = False, remove: bool = False, say=print
) -> int:
    """Convert ``folder``'s pickles (see the module docstring); returns how many.
    ``allow_pickle`` must be True: it is the caller's word that the folder is trusted.
    ``policy_only`` strips the final model alone (a zoo entry's); checkpoints and the best
    model keep what training on needs."""
    from .train import algorithm_class

    if not allow_pickle:
        raise RunError(
            f"{folder}: converting loads SB3's pickles, which runs any code they carry: "
            "allow_pickle=True (--allow-pickle) for a folder whose source you trust"
        )
    if not (folder / "config.yaml").is_file():
        raise RunError(f"{folder}: not a run folder or zoo entry (no config.yaml)")
    algo_cls = algorithm_class(load_config(folder / "config.yaml").algorithm.name)
    final = folder / MODEL
    done = 0
    for old, new, kind in pickled_pairs(folder):
        if new.is_file():
            say(f"{new}: there already; {old.name} left as it is")
            continue
        if kind == "model":
            model = saved.load_pickled_model(algo_cls, old)
            strip = policy_only and new == final
            files.write_with(new, lambda tmp, m=model, p=strip: saved.save_model(m, tmp, p))
        elif kind == "statistics":
            stats = saved.load_pickled_vec_normalize(old)
            files.write_with(new, lambda tmp, v=stats: saved.save_statistics(v, tmp))
        else:
            buffer = saved.load_pickled_replay(old)
            files.write_with(new, lambda tmp, b=buffer: saved.save_replay(b, tmp))
        if remove:
            old.unlink()
        say(f"{old} -> {new.name}")
        done += 1
    return done


def main(argv: list[str] | None = None) -> int:
    prog = "python -m fluidsim_envs.rl.convert"
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.split("\n\n")[0])
    parser.add_argument("folders", type=Path, nargs="+", metavar="FOLDER")
    parser.add_argument(
        "--allow-pickle",
        action="store_true",
        help="required: loading the pickles runs any code they carry; give it only for "
        "folders whose source you trust",
    )
    parser.add_argument("--policy-only", action="store_true", help="the policy's weights alone")
    parser.add_argument("--remove", action="store_true", help="delete each converted pickle")
    args = parser.parse_args(argv)
    if not args.allow_pickle:
        print(
            f"{prog}: error: converting loads SB3's pickles, which runs any code they carry: "
            "pass --allow-pickle for folders whose source you trust",
            file=sys.stderr,
        )
        return 2
    try:
        for folder in args.folders:
            n = convert(folder, allow_pickle=True, policy_only=args.policy_only,
                        remove=args.remove)  # fmt: skip
            print(f"{folder}: {n} file{'s' * (n != 1)} converted")
    except (RunError, ConfigError) as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
