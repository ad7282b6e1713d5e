"""Writes the image harness's seeds, tests/fuzz/corpus/image: the valid
one-colour images of every format and the malformed ones of
tests/python/image_files.py (each under 2 KB). Rerun after changing
image_files.py: build/venv/bin/python tests/fuzz/make_image_seeds.py"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "python"))

import image_files  # noqa: E402

corpus = HERE / "corpus" / "image"
corpus.mkdir(parents=True, exist_ok=True)
for old in corpus.iterdir():
    old.unlink()
for name, (data, _) in {**image_files.valid_images(), **image_files.malformed_images()}.items():
    (corpus / name).write_bytes(data)
