"""What a campaign leaves a user: the report (`report`) and its figures (`figures`), its
calibration for the PFC export (`export`; the writers are `rockcal.pfc`'s), user text checked for
generated files (`safe_text`)."""
