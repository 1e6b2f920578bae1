"""The example scenarios and campaigns shipped inside the package (examples/*.yaml that need no file outside
examples/, and the mission files they fly), so that scripts and notebooks find them from any folder."""
import os

EXAMPLES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "examples")


def example_files():
    """The names example_file() accepts, sorted."""
    if not os.path.isdir(EXAMPLES_DIR):
        return []
    return sorted(name for name in os.listdir(EXAMPLES_DIR) if name.endswith(".yaml"))


def example_file(name):
    """The path of a shipped example, e.g. example_file("jam-motor-3.yaml"), for load_scenario, run,
    Environment or run_campaign. InputError naming the examples there are when it is not one of them."""
    path = os.path.join(EXAMPLES_DIR, os.path.basename(os.fspath(name)))
    if not os.path.isfile(path):
        from ._uascma import InputError

        raise InputError(f"example_file: {name}: one of {', '.join(example_files()) or '(none: the package was built without them)'}")
    return path
