"""Pictures for people: level renders, contact sheets and episode GIFs (numpy + Pillow, on the host)."""
