"""What every part of the generator shares."""

SOURCE_EXTENSIONS = (".h", ".hpp", ".cpp", ".cc")


class KitError(Exception):
    pass
