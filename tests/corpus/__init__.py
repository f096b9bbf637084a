"""Malformed and hostile inputs the project writes itself (``make_corpus.py``), one case per rule of the input policy;
``tests/test_corpus.py`` runs ``bake``, ``inspect`` and ``validate`` on each."""
