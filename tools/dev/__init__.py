"""Developer aids: surface frames at scale, random CCD queries, run comparisons, sample meshes."""
