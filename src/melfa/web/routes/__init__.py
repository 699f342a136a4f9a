"""One router per resource; `melfa.web.app` includes them all."""
