"""gearsim.viz"""
