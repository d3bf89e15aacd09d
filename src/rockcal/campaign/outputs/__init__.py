"""What a campaign leaves a user: the report (`report`) and its figures (`figures`), the PFC
export (`export`), user text made safe in generated files (`safe_text`)."""
