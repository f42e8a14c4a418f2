"""gearsim.dynamics"""
