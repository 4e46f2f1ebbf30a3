"""What the command-line check scripts share: failures collected by check(), the Python modules
an image-reading check needs, and CTest's exit code (0 pass, 1 fail).

A check script puts this folder on sys.path (tests/tools, beside image_compare.py), imports
check and FAILURES, and ends with `sys.exit(1 if FAILURES else 0)` or its own summary."""
import sys

FAILURES = []


def check(condition, message):
    """Records and prints a failure when `condition` is false. Returns the condition, so that a
    check can guard the ones that only make sense after it."""
    if not condition:
        FAILURES.append(message)
        print(f"FAIL: {message}")
    return condition


def exit_code(passed_message=""):
    """0 with `passed_message` printed when no check failed, else 1 with the count on stderr."""
    if FAILURES:
        print(f"{len(FAILURES)} failed", file=sys.stderr)
        return 1
    if passed_message:
        print(passed_message)
    return 0


def import_oiio():
    """OpenImageIO's Python module, or a failure (not a skip: install-deps.sh installs it)."""
    try:
        import OpenImageIO
    except ImportError as e:  # pragma: no cover
        sys.exit(f"FAIL: {e} (scripts/install-deps.sh installs python3-openimageio)")
    return OpenImageIO


def import_numpy_oiio():
    """numpy and OpenImageIO's Python module, or a failure naming the packages."""
    try:
        import numpy
        import OpenImageIO
    except ImportError as e:  # pragma: no cover
        sys.exit(f"FAIL: {e} (scripts/install-deps.sh installs python3-numpy and python3-openimageio)")
    return numpy, OpenImageIO
