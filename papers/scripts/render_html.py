#!/usr/bin/env python3
"""index.md -> index.html for `ldlpgs report`, with Debian's python3-markdown (tables extension).

Usage: python3 papers/scripts/render_html.py INDEX.md INDEX.html
Images keep their relative links, so the HTML page sits beside the figures it shows.
"""
import sys

from debian_python import require

markdown = require("markdown", "python3-markdown")

STYLE = """body { font-family: sans-serif; max-width: 75em; margin: 2em auto; line-height: 1.4; }
table { border-collapse: collapse; font-size: 0.85em; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }
th:first-child, td:first-child { text-align: left; }
code, pre { background: #f4f4f4; }
img { max-width: 100%; }"""


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip())
    source, target = sys.argv[1], sys.argv[2]
    with open(source, encoding="utf-8") as f:
        text = f.read()
    body = markdown.markdown(text, extensions=["tables", "fenced_code", "toc"])
    title = next((line[2:].strip() for line in text.splitlines() if line.startswith("# ")), "ldlpgs report")
    with open(target, "w", encoding="utf-8") as f:
        f.write(f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{title}</title>\n"
                f"<style>\n{STYLE}\n</style></head>\n<body>\n{body}\n</body></html>\n")


if __name__ == "__main__":
    main()
