"""Exit 0 when every requirement in the given file is installed at a matching version (no network)."""

import sys
from importlib import metadata

try:
    from packaging.requirements import Requirement
except ImportError:  # a bare machine: let pip install everything
    print("packaging is not installed")
    sys.exit(1)


def main(path: str) -> int:
    missing = []
    for line in open(path):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        requirement = Requirement(line)
        try:
            version = metadata.version(requirement.name)
        except metadata.PackageNotFoundError:
            missing.append(requirement.name)
            continue
        if requirement.specifier and not requirement.specifier.contains(version, prereleases=True):
            missing.append(f"{requirement.name} {version} (need {requirement.specifier})")
    if missing:
        print("missing Python packages: " + ", ".join(missing))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
