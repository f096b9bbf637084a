"""File formats: glTF documents, USD stages and images. No algorithms live here."""
