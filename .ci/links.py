"""Every relative link of the README and the guide names a file of the repository."""
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parent.parent
pages = [root / "README.md", *sorted((root / "docs" / "guide").glob("*.md"))]
broken = []
for page in pages:
    fence = False
    for number, line in enumerate(page.read_text().splitlines(), 1):
        if line.startswith("```"):
            fence = not fence
        if fence:
            continue
        for target in re.findall(r"\]\(([^)\s]+)\)", line):
            if re.match(r"^(https?:|mailto:|#)", target):
                continue
            path = (page.parent / target.split("#")[0]).resolve()
            if not path.exists():
                broken.append(f"{page.relative_to(root)}:{number}: no such file: {target}")
print("\n".join(broken) or f"links: {len(pages)} pages, every relative link resolves")
sys.exit(1 if broken else 0)
