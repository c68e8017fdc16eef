#!/usr/bin/env python3
"""Writes docs/reference/python.md, the Python module's API reference, from
the docstrings and signatures of what `fibrodem.__all__` exports.

Usage: PYTHONPATH=build/python scripts/python_reference.py > docs/reference/python.md
       scripts/python_reference.py --check FILE   (exit 1, naming the file, if FILE differs)
"""
import inspect
import sys

import fibrodem


def doc(obj):
    return inspect.cleandoc(obj.__doc__ or "(no docstring)")


def signature(name, obj):
    try:
        return name + str(inspect.signature(obj))
    except (TypeError, ValueError):
        return name


def block(text):
    return "```\n" + text + "\n```\n"


def members(cls):
    """The public methods and properties a class defines itself, in source order."""
    for name, member in vars(cls).items():
        if not name.startswith("_") and (callable(member) or isinstance(member, property)):
            yield name, member


def page():
    out = ["# Python module `fibrodem`", "",
           "Written from the module's docstrings by `scripts/python_reference.py`; a test",
           "checks that this page is current. How to install and use it:",
           "[guide/python.md](../guide/python.md).", "", block(doc(fibrodem)).rstrip(), ""]
    for name in fibrodem.__all__:
        obj = getattr(fibrodem, name)
        if inspect.isclass(obj):
            out += ["## class " + name, "", block(doc(obj)).rstrip(), ""]
            for member_name, member in members(obj):
                if isinstance(member, property):
                    out += ["### " + name + "." + member_name + " (property)", "", block(doc(member)).rstrip(), ""]
                else:
                    out += ["### " + name + "." + member_name, "", "`" + signature(member_name, member) + "`", "",
                            block(doc(member)).rstrip(), ""]
        else:
            out += ["## " + name, "", "`" + signature(name, obj) + "`", "", block(doc(obj)).rstrip(), ""]
    return "\n".join(out)


def main():
    text = page()
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        with open(sys.argv[2]) as f:
            if f.read() != text:
                print("%s is not what the docstrings give now: regenerate it with "
                      "PYTHONPATH=build/python scripts/python_reference.py > %s" % (sys.argv[2], sys.argv[2]))
                return 1
        return 0
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
