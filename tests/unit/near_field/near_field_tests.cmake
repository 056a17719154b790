# near_field tests (filled in by the work on this area).
