"""gearsim.fem"""
