"""The exceptions of the fibrodem package."""


class ManifestError(ValueError):
    """A manifest value is wrong: the command line's exit status 2.

    Attributes:
        path: the dotted JSON path of the offending value, e.g.
            ``"coupling.D_f_nS"`` or ``"stimulus[0].amplitude_pA"`` (``""``: the
            manifest as a whole).
        expected: what was expected there (the message without the path).
    """

    def __init__(self, message, path="", expected=""):
        super().__init__(message)
        self.path = path
        self.expected = expected


class PluginError(RuntimeError):
    """A cell-model plugin is missing or faulty: the command line's exit status 3."""


class RunError(RuntimeError):
    """The run failed (a blow-up, a full disk, ...): the command line's exit status 4.

    Attributes:
        result: the Result up to the failure (with ``out``, the folder keeps
            what was written and its summary.json says ``failed``).
    """

    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result
