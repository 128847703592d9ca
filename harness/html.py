"""The HTML report (filled in later)."""


def write_html(result, path) -> None:
    raise NotImplementedError("the HTML report is not built yet")
